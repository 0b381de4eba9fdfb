// The few UnityEngine types the Unity sample (clients/csharp/unity/Samples/HapticWall.cs) uses, so that the
// sample compiles in the tests without Unity (which is not run here): signatures only, as Unity documents them.
namespace UnityEngine
{
    public struct Vector3
    {
        public float x, y, z;
        public Vector3(float x, float y, float z) { this.x = x; this.y = y; this.z = z; }
    }
    public class Transform { public Vector3 position; }
    public class Object { }
    public class Component : Object { public Transform transform = new Transform(); }
    public class Behaviour : Component { public bool enabled = true; }
    public class MonoBehaviour : Behaviour { }
    public static class Debug
    {
        public static void Log(object message) { }
        public static void LogError(object message) { }
    }
    public class SerializeField : System.Attribute { }
}
