// A Unity sample: the colliders under this GameObject become the server's haptic scene (docs/haptic-scene.md), felt
// at the server's loop rate whatever Unity's frame rate. Box, sphere and capsule colliders are added once (a
// collider with a non-kinematic Rigidbody as a moving object); every frame the moving ones are moved to where Unity's
// physics put them, and the hands' contacts - read on a thread of their own, never on Unity's - push the
// Rigidbodies (AddForceAtPosition). Start `hapticd --config config/sessions/vishard3/dds-scene.yaml`, add this to the
// root of the colliders to feel, press Play. Units: 1 Unity unit = 1 m. Frames: Unity's y is up and its axes are
// left-handed, hapticd's z is up (right-handed): a point (x, y, z) in Unity is (x, z, y) in hapticd's world, offset by
// `origin` (the hapticd world point at Unity's origin; a ViSHaRD3's handle starts near [0.067, 0.279, 0]).
// Not run in Unity by this project: compiled against a stand-in of the UnityEngine types it uses (tests/csharp).
using System;
using System.Collections.Generic;
using System.Globalization;
using System.Threading;
using Hapticd;
using UnityEngine;

public class HapticSceneMirror : MonoBehaviour
{
    [SerializeField] public int domain = 0;
    [SerializeField] public Vector3 origin = new Vector3(0.067f, 0.279f, 0f);  // hapticd's world at Unity's origin
    [SerializeField] public string material = "{\"stiffness\": 2500, \"damping\": 5}";

    class Mirrored
    {
        public string name;
        public Collider collider;
        public Rigidbody body;  // null: still
    }

    Client client_;
    readonly List<Mirrored> objects_ = new List<Mirrored>();
    readonly Dictionary<string, Mirrored> byName_ = new Dictionary<string, Mirrored>();
    SceneContact[] contacts_ = new SceneContact[0];  // the newest the reader thread took
    readonly object contactsLock_ = new object();
    Thread reader_;
    volatile bool stopping_;

    void Start()
    {
        try
        {
            client_ = new Client("unity-scene-mirror", domain);
            client_.SceneClaim(10.0);
            int n = 0;
            foreach (var c in GetComponentsInChildren<Collider>())
            {
                var m = new Mirrored { name = "unity" + (n++) + "-" + c.name, collider = c, body = c.GetComponent<Rigidbody>() };
                if (m.body != null && m.body.isKinematic) m.body = null;
                if (m.name.Length > 31) m.name = m.name.Substring(0, 31);
                string json = ObjectJson(m);
                if (json == null) continue;  // a collider the scene has no shape for (a mesh collider: upload it instead)
                client_.SceneAdd(json);
                objects_.Add(m);
                byName_[m.name] = m;
            }
            reader_ = new Thread(ReadContacts) { IsBackground = true };
            reader_.Start();
        }
        catch (HapticdException e)
        {
            Debug.LogError("hapticd: " + e.Status + ": " + e.Message);
            enabled = false;
        }
    }

    // Unity -> hapticd: points swap y and z and are offset by `origin`; a rotation's quaternion (w, x, y, z) becomes
    // (w, -x, -z, -y) (the swap is a reflection: the axis is reflected and the angle turns the other way).
    Vec3 ToHapticd(Vector3 p) { return new Vec3(p.x + origin.x, p.z + origin.y, p.y + origin.z); }
    static Quat ToHapticd(Quaternion q) { return new Quat { w = q.w, x = -q.x, y = -q.z, z = -q.y }; }
    // hapticd -> Unity: a point, and a direction (a force).
    Vector3 PointToUnity(Vec3 p) { return new Vector3((float)(p.x - origin.x), (float)(p.z - origin.z), (float)(p.y - origin.y)); }
    static Vector3 DirectionToUnity(Vec3 v) { return new Vector3((float)v.x, (float)v.z, (float)v.y); }

    // The scene object's pose: the collider's centre, its rotation (a capsule's axis turned onto the object's z).
    Pose PoseOf(Collider c)
    {
        var t = c.transform;
        Vector3 centre = new Vector3(0, 0, 0);
        Quaternion rotation = t.rotation;
        var box = c as BoxCollider;
        var sphere = c as SphereCollider;
        var capsule = c as CapsuleCollider;
        if (box != null) centre = box.center;
        if (sphere != null) centre = sphere.center;
        if (capsule != null)
        {
            centre = capsule.center;
            // The axis (Unity's direction 0, 1, 2: the collider's x, y, z) must be hapticd's object z, which is
            // Unity's y after the swap: a y capsule needs no turn, an x or a z one is turned onto y.
            if (capsule.direction == 0) rotation = rotation * Quaternion.Euler(0, 0, 90);
            else if (capsule.direction == 2) rotation = rotation * Quaternion.Euler(90, 0, 0);
        }
        return new Pose { position = ToHapticd(t.TransformPoint(centre)), orientation = ToHapticd(rotation) };
    }

    // The collider as the scene file writes an object; null for a kind the scene has no shape for.
    string ObjectJson(Mirrored m)
    {
        var s = m.collider.transform.lossyScale;
        var box = m.collider as BoxCollider;
        var sphere = m.collider as SphereCollider;
        var capsule = m.collider as CapsuleCollider;
        string shape;
        if (box != null)  // Unity's edges along its x, y, z are hapticd's along x, z, y
            shape = F("\"shape\": \"box\", \"size\": [{0}, {1}, {2}]", box.size.x * s.x, box.size.z * s.z, box.size.y * s.y);
        else if (sphere != null)
            shape = F("\"shape\": \"sphere\", \"radius\": {0}", sphere.radius * Math.Max(s.x, Math.Max(s.y, s.z)));
        else if (capsule != null)
        {
            double r = capsule.radius * Math.Max(s.x, s.z);
            shape = F("\"shape\": \"capsule\", \"radius\": {0}, \"length\": {1}", r,
                      Math.Max(0.0, capsule.height * s.y - 2 * r));
        }
        else
            return null;
        var pose = PoseOf(m.collider);
        var p = pose.position;
        var q = pose.orientation;
        return "{\"name\": \"" + m.name + "\", " + shape +
               F(", \"position\": [{0}, {1}, {2}], \"quaternion\": [{3}, {4}, {5}, {6}]", p.x, p.y, p.z, q.w, q.x, q.y, q.z) +
               ", \"material\": " + material + ", \"moving\": " + (m.body != null ? "true" : "false") + "}";
    }

    static string F(string format, params object[] values) { return string.Format(CultureInfo.InvariantCulture, format, values); }

    // Its own thread: the hands' contacts at about 60 Hz (a request and its answer; never on Unity's thread).
    void ReadContacts()
    {
        while (!stopping_)
        {
            try
            {
                var c = client_.SceneContacts(1.0);
                lock (contactsLock_) contacts_ = c;
            }
            catch (HapticdException) { }
            Thread.Sleep(16);
        }
    }

    // Unity's physics step: the hands push the bodies; then the bodies' new poses go to the server.
    void FixedUpdate()
    {
        SceneContact[] contacts;
        lock (contactsLock_) contacts = contacts_;
        foreach (var c in contacts)
        {
            Mirrored m;
            if (!byName_.TryGetValue(c.ObjectName, out m) || m.body == null) continue;
            m.body.AddForceAtPosition(DirectionToUnity(c.force), PointToUnity(c.point));
        }
        foreach (var m in objects_)
        {
            if (m.body == null) continue;
            var pose = PoseOf(m.collider);
            try { client_.SceneMove(m.name, ref pose); } catch (HapticdException) { }
        }
    }

    void OnDestroy()
    {
        stopping_ = true;
        if (reader_ != null) reader_.Join();
        if (client_ != null)
        {
            try
            {
                foreach (var m in objects_) client_.SceneRemove(m.name);
                client_.SceneRelease();
            }
            catch (HapticdException) { }
            client_.Dispose();
        }
    }
}
