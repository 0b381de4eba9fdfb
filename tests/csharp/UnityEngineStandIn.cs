// The few UnityEngine types the Unity samples (clients/csharp/unity/Samples: HapticWall.cs, HapticSceneMirror.cs) use,
// so that the samples compile in the tests without Unity (which is not run here): signatures only, as Unity
// documents them.
namespace UnityEngine
{
    public struct Vector3
    {
        public float x, y, z;
        public Vector3(float x, float y, float z) { this.x = x; this.y = y; this.z = z; }
    }
    public struct Quaternion
    {
        public float x, y, z, w;
        public static Quaternion Euler(float x, float y, float z) { return new Quaternion(); }
        public static Quaternion operator *(Quaternion a, Quaternion b) { return a; }
    }
    public class Transform
    {
        public Vector3 position;
        public Quaternion rotation;
        public Vector3 lossyScale;
        public Vector3 TransformPoint(Vector3 p) { return p; }
    }
    public class Object { public string name = ""; }
    public class Component : Object
    {
        public Transform transform = new Transform();
        public T GetComponent<T>() { return default(T); }
        public T[] GetComponentsInChildren<T>() { return new T[0]; }
    }
    public class Collider : Component { }
    public class BoxCollider : Collider { public Vector3 center, size; }
    public class SphereCollider : Collider { public Vector3 center; public float radius; }
    public class CapsuleCollider : Collider { public Vector3 center; public float radius, height; public int direction; }
    public class Rigidbody : Component
    {
        public bool isKinematic;
        public void AddForceAtPosition(Vector3 force, Vector3 position) { }
    }
    public class Behaviour : Component { public bool enabled = true; }
    public class MonoBehaviour : Behaviour { }
    public static class Debug
    {
        public static void Log(object message) { }
        public static void LogError(object message) { }
    }
    public class SerializeField : System.Attribute { }
}
