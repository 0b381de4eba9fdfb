// A Unity sample: the device's handle moves this GameObject, and a wall at `wallX` (metres along the device's x,
// ahead of where the handle starts) is rendered through the server's virtual coupling. Add it to a GameObject,
// start `hapticd --config config/sessions/vishard3/dds-coupling.yaml` (or a commercial device's engine session),
// press Play. The engine answers every state on the DDS receive thread (Hapticd.Engine); Update() only moves the
// GameObject from the newest state. Not run in Unity by this project (docs/engines.md, "C# and Unity").
using Hapticd;
using UnityEngine;

public class HapticWall : MonoBehaviour
{
    [SerializeField] public string device = "vishard3";
    [SerializeField] public int domain = 0;
    [SerializeField] public float wallX = 0.02f;      // m ahead of the handle's start
    [SerializeField] public float metresToUnits = 10f;

    Client client_;
    Engine engine_;
    DeviceName name_;
    double wallWorldX_;
    double startX_;

    void Start()
    {
        try
        {
            client_ = new Client("unity-haptic-wall", domain);
            var first = client_.WaitForState(device, 10.0);
            startX_ = first.pose.position.x;
            wallWorldX_ = startX_ + wallX;
            name_ = new DeviceName(device);
            engine_ = new Engine(client_, device, Render);
            engine_.Start();
        }
        catch (HapticdException e)
        {
            Debug.LogError("hapticd: " + e.Status + ": " + e.Message);
            enabled = false;
        }
    }

    // The DDS receive thread: the proxy is the handle held back at the wall (no allocation).
    void Render(ref DeviceState s, ref Command c)
    {
        var proxy = s.pose;
        if (proxy.position.x > wallWorldX_) proxy.position.x = wallWorldX_;
        c = Command.Coupling(proxy, new Twist(), s.serial);
    }

    void Update()
    {
        if (engine_ == null) return;
        if (engine_.ClaimLost)
        {
            string why;
            if (!engine_.Reclaim(out why)) Debug.LogError("hapticd: the device is another client's now: " + why);
        }
        DeviceState s;
        if (client_.TryLatestState(name_, out s))
            transform.position = new Vector3((float)(s.pose.position.x - startX_) * metresToUnits,
                                             (float)s.pose.position.z * metresToUnits,
                                             (float)s.pose.position.y * metresToUnits);
    }

    void OnDestroy()
    {
        if (engine_ != null) engine_.Dispose();
        if (client_ != null) client_.Dispose();
    }
}
