// A Unity sample: the device's handle moves this GameObject, and a wall at `wallX` (metres along the device's x,
// ahead of where the handle starts) is rendered through the server's virtual coupling. Add it to a GameObject,
// start `hapticd --config config/sessions/vishard3/dds-coupling.yaml` (or a commercial device's engine session),
// press Play. The engine finds, claims and answers every state off the main thread (Hapticd.Engine: its own thread
// and the DDS receive thread); Update() only moves the GameObject from the newest state, never waits. Not run in Unity by this project (docs/engines.md, "C# and Unity").
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
    bool told_;

    // Nothing here waits: the engine finds the device, claims it and answers its states on threads of its own.
    void Start()
    {
        try
        {
            client_ = new Client("unity-haptic-wall", domain);
            name_ = new DeviceName(device);
            engine_ = new Engine(client_, device, Render, 20.0, "unity-haptic-wall");
            engine_.Start();
        }
        catch (HapticdException e)
        {
            Debug.LogError("hapticd: " + e.Status + ": " + e.Message);
            enabled = false;
        }
    }

    // The DDS receive thread, once the device is claimed: the proxy is the handle held back at the wall (no
    // allocation).
    void Render(ref DeviceState s, ref Command c)
    {
        var proxy = s.pose;
        double wall = engine_.StartPose.position.x + wallX;
        if (proxy.position.x > wall) proxy.position.x = wall;
        c = Command.Coupling(proxy, new Twist(), 0);
    }

    // The main thread reads the newest state only (the engine retakes a lost claim by itself).
    void Update()
    {
        if (engine_ == null) return;
        if (engine_.Ended && !told_)
        {
            told_ = true;
            Debug.LogError("hapticd: the engine ended: " + engine_.EndReason + ": " + engine_.EndMessage);
        }
        DeviceState s;
        if (!engine_.Claimed || !client_.TryLatestState(name_, out s)) return;
        double startX = engine_.StartPose.position.x;
        transform.position = new Vector3((float)(s.pose.position.x - startX) * metresToUnits,
                                         (float)s.pose.position.z * metresToUnits,
                                         (float)s.pose.position.y * metresToUnits);
    }

    void OnDestroy()
    {
        if (engine_ != null) engine_.Dispose();
        if (client_ != null) client_.Dispose();
    }
}
