// hapticd's C API (hapticd/client.h) for C#: the P/Invoke declarations and the spatial structs; the value structs,
// field for field the C ones (blittable: fixed-size buffers, no marshalled strings, so a state is read and a command
// sent without a managed allocation), are generated into NativeTypes.g.cs. The c_api_abi test holds the C layouts; this assembly's test holds these to the same file.
using System;
using System.Runtime.InteropServices;

namespace Hapticd
{
    [StructLayout(LayoutKind.Sequential)]
    public struct Vec3 { public double x, y, z; public Vec3(double x, double y, double z) { this.x = x; this.y = y; this.z = z; } }

    [StructLayout(LayoutKind.Sequential)]
    public struct Quat { public double w, x, y, z; public static readonly Quat Identity = new Quat { w = 1 }; }

    [StructLayout(LayoutKind.Sequential)]
    public struct Pose { public Vec3 position; public Quat orientation; }

    [StructLayout(LayoutKind.Sequential)]
    public struct Twist { public Vec3 linear, angular; }

    [StructLayout(LayoutKind.Sequential)]
    public struct Wrench { public Vec3 force, torque; }

    public enum Status { Ok = 0, InvalidArgument = 1, NotFound = 2, Timeout = 3, Refused = 4, Dds = 5, Internal = 6 }

    [Flags]
    public enum StateFlags : uint
    {
        TorqueSaturated = 1u << 0, EngineActive = 1u << 1, EngineStale = 1u << 2, Estop = 1u << 3, Fault = 1u << 4,
        Switching = 1u << 5, SafeDamping = 1u << 6, LimitEngaged = 1u << 7, RenderLimited = 1u << 8,
        ThermalDerating = 1u << 9, PassivityControl = 1u << 10
    }

    // The value structs (DeviceState, DeviceInfo, GroupState, Event, Telemetry, FaultReport, Reply, Command, ...) are
    // generated from idl/hapticd_wire.toml into NativeTypes.g.cs, with their fields and text accessors; what follows
    // adds the helpers the table does not describe, in the other part of each partial struct.
    public partial struct DeviceState
    {
        public StateFlags Flags { get { return (StateFlags)flags; } }
    }

    public partial struct DeviceInfo
    {
        public string SchemeName(int i) { return Scheme(i).Name; }
    }

    public unsafe partial struct Reply
    {
        public double Value(int i) { if (i < 0 || i >= Limits.MaxValues) throw new ArgumentOutOfRangeException("i"); fixed (double* v = values) return v[i]; }
    }

    public unsafe partial struct LocalModel
    {
        // A spring and damper about `anchor`, per axis (N/m, N s/m): the server applies it every cycle until the
        // next command, so a wall rendered at the engine's frame rate is felt at the loop's. Made in a local here:
        // a fixed buffer written through a field needs pinning (CS1666), a local does not.
        public static LocalModel Spring(Pose anchor, Vec3 stiffness, Vec3 damping)
        {
            return Spring(anchor, stiffness, damping, new Vec3(), new Vec3());
        }
        // The same with a rotational spring and damper (N m/rad, N m s/rad) about the anchor's orientation.
        public static LocalModel Spring(Pose anchor, Vec3 stiffness, Vec3 damping, Vec3 rotationalStiffness,
                                        Vec3 rotationalDamping)
        {
            var m = new LocalModel { anchor = anchor };
            m.stiffness[0] = stiffness.x; m.stiffness[1] = stiffness.y; m.stiffness[2] = stiffness.z;
            m.stiffness[3] = rotationalStiffness.x; m.stiffness[4] = rotationalStiffness.y; m.stiffness[5] = rotationalStiffness.z;
            m.damping[0] = damping.x; m.damping[1] = damping.y; m.damping[2] = damping.z;
            m.damping[3] = rotationalDamping.x; m.damping[4] = rotationalDamping.y; m.damping[5] = rotationalDamping.z;
            return m;
        }
    }

    public partial struct Command
    {
        public static Command Coupling(Pose proxy, Twist proxyTwist, ulong stateSerial)
        {
            return new Command { kind = (int)CommandKind.Coupling, pose = proxy, twist = proxyTwist, state_serial = stateSerial };
        }
        public static Command Force(Wrench wrench, ulong stateSerial)
        {
            var c = new Command { kind = (int)CommandKind.Wrench, wrench = wrench, state_serial = stateSerial };
            c.pose.orientation = Quat.Identity;
            return c;
        }
        // A wrench with a local model: wrench + stiffness .* (anchor - x) - damping .* xd, every cycle until the next.
        public static Command Force(Wrench wrench, LocalModel model, ulong stateSerial)
        {
            var c = Force(wrench, stateSerial);
            c.has_local_model = 1;
            c.local_model = model;
            return c;
        }
        public static Command Motion(Pose pose, Twist twist, ulong stateSerial)
        {
            return new Command { kind = (int)CommandKind.Motion, pose = pose, twist = twist, state_serial = stateSerial };
        }
    }

    // hapticd_client_options
    [StructLayout(LayoutKind.Sequential)]
    public struct ClientOptions
    {
        public uint size;
        public IntPtr client_id;
        public int domain_id;
        public IntPtr cyclone_config;
        public IntPtr network;
        public double command_deadline_s;
    }

    static unsafe class Text
    {
        // A zero-terminated UTF-8 text of at most `size` bytes.
        public static string Of(byte* p, int size)
        {
            int n = 0;
            while (n < size && p[n] != 0) ++n;
            return System.Text.Encoding.UTF8.GetString(p, n);
        }
        // A name as the C API takes it: UTF-8, zero-terminated (made once, kept: no per-cycle garbage).
        public static byte[] Name(string text)
        {
            var bytes = System.Text.Encoding.UTF8.GetBytes(text ?? "");
            var z = new byte[bytes.Length + 1];
            Buffer.BlockCopy(bytes, 0, z, 0, bytes.Length);
            return z;
        }
    }

    // hapticd_engine_options
    [StructLayout(LayoutKind.Sequential)]
    public struct EngineOptions
    {
        public uint size;
        public IntPtr name, device, group;
        public double wait_s, server_timeout_s, duration_s;
        public int wait_for_server;
    }

    public enum EngineEndReason { Finished = 0, Stopped = 1, SessionEnded = 2, NoDevice = 3, ClaimRefused = 4, ClaimLost = 5, Failed = 6 }

    // hapticd_engine_end
    [StructLayout(LayoutKind.Sequential)]
    public unsafe struct EngineEnd
    {
        public int reason, exit_code;
        public fixed byte message[256];
        public string Message { get { fixed (byte* p = message) return Text.Of(p, 256); } }
        public EngineEndReason Reason { get { return (EngineEndReason)reason; } }
    }

    // The native callbacks' types. Only static methods marked [MonoPInvokeCallback] are handed to native code (IL2CPP
    // marshals no instance delegate); the object they serve comes back in `user` as a GCHandle.
    [UnmanagedFunctionPointer(CallingConvention.Cdecl)]
    unsafe delegate int EngineAnswer(DeviceState* states, int count, Command* commands, IntPtr user);
    [UnmanagedFunctionPointer(CallingConvention.Cdecl)]
    delegate int EngineClaimHook(int again, IntPtr user);

    // What IL2CPP looks for (by name) on a static method it must make callable from native code; Unity's own is
    // AOT.MonoPInvokeCallbackAttribute, and one of this name in any namespace does the same.
    [AttributeUsage(AttributeTargets.Method)]
    public sealed class MonoPInvokeCallbackAttribute : Attribute
    {
        public MonoPInvokeCallbackAttribute(Type type) { Type = type; }
        public Type Type { get; private set; }
    }

    [UnmanagedFunctionPointer(CallingConvention.Cdecl)]
    unsafe delegate void StateCallback(DeviceState* state, IntPtr user);
    [UnmanagedFunctionPointer(CallingConvention.Cdecl)]
    unsafe delegate void EventCallback(Event* e, IntPtr user);
    [UnmanagedFunctionPointer(CallingConvention.Cdecl)]
    delegate void ClaimLostCallback(IntPtr device, IntPtr reason, IntPtr user);
    [UnmanagedFunctionPointer(CallingConvention.Cdecl)]
    delegate int EngineChoresHook(IntPtr user);
    [UnmanagedFunctionPointer(CallingConvention.Cdecl)]
    unsafe delegate void EngineParameterHook(Event* e, ulong answeredThen, IntPtr user);

    // Every function of the C API (hapticd/client.h, version 2), in its order; the csharp test checks the list
    // against the library's exported symbols. Names are zero-terminated UTF-8 byte arrays (blittable: pinned, not
    // copied). A pointer the C API lets be NULL has an IntPtr overload.
    static unsafe class Native
    {
        const string Lib = "hapticd_c";
        [DllImport(Lib)] public static extern int hapticd_api_version();
        [DllImport(Lib)] public static extern IntPtr hapticd_last_error();
        [DllImport(Lib)] public static extern IntPtr hapticd_status_name(Status status);
        [DllImport(Lib)] public static extern Status hapticd_client_create(ref ClientOptions options, out ClientHandle client);
        [DllImport(Lib)] public static extern void hapticd_client_destroy(IntPtr client);
        // devices
        [DllImport(Lib)] public static extern Status hapticd_client_list_devices(ClientHandle c, [Out] DeviceInfo[] output, int capacity, out int count);
        [DllImport(Lib)] public static extern Status hapticd_client_wait_for_device(ClientHandle c, byte[] device, double timeout, int started, out DeviceInfo info);
        [DllImport(Lib)] public static extern Status hapticd_client_latest_state(ClientHandle c, byte[] device, out DeviceState state);
        [DllImport(Lib)] public static extern Status hapticd_client_wait_for_state(ClientHandle c, byte[] device, double timeout, ulong after, out DeviceState state);
        // groups
        [DllImport(Lib)] public static extern Status hapticd_client_list_groups(ClientHandle c, [Out] GroupInfo[] output, int capacity, out int count);
        [DllImport(Lib)] public static extern Status hapticd_client_wait_for_group(ClientHandle c, byte[] group, double timeout, out GroupInfo info);
        [DllImport(Lib)] public static extern Status hapticd_client_latest_group_state(ClientHandle c, byte[] group, out GroupState state);
        [DllImport(Lib)] public static extern Status hapticd_client_wait_for_group_state(ClientHandle c, byte[] group, double timeout, ulong after, out GroupState state);
        // events, telemetry, fault reports
        [DllImport(Lib)] public static extern Status hapticd_client_take_events(ClientHandle c, [Out] Event[] output, int capacity, out int count);
        [DllImport(Lib)] public static extern Status hapticd_client_latest_telemetry(ClientHandle c, byte[] device, out Telemetry telemetry);
        [DllImport(Lib)] public static extern Status hapticd_client_latest_fault_report(ClientHandle c, byte[] device, out FaultReport report);
        // callbacks
        [DllImport(Lib)] public static extern Status hapticd_client_on_state(ClientHandle c, byte[] device, StateCallback callback, IntPtr user);
        [DllImport(Lib)] public static extern Status hapticd_client_on_event(ClientHandle c, EventCallback callback, IntPtr user);
        [DllImport(Lib)] public static extern Status hapticd_client_on_claim_lost(ClientHandle c, ClaimLostCallback callback, IntPtr user);
        [DllImport(Lib)] public static extern Status hapticd_client_claim_lost(ClientHandle c, byte[] device, out int lost);
        // requests (a target: a device or a group)
        [DllImport(Lib)] public static extern Status hapticd_client_claim(ClientHandle c, byte[] target, double timeout, out Reply reply);
        [DllImport(Lib)] public static extern Status hapticd_client_release(ClientHandle c, byte[] target, double timeout, out Reply reply);
        [DllImport(Lib)] public static extern Status hapticd_client_switch_scheme(ClientHandle c, byte[] device, byte[] scheme, double timeout, out Reply reply);
        [DllImport(Lib)] public static extern Status hapticd_client_set_parameter(ClientHandle c, byte[] device, byte[] parameter, double[] values, int count, double timeout, out Reply reply);
        [DllImport(Lib)] public static extern Status hapticd_client_get_parameter(ClientHandle c, byte[] device, byte[] parameter, double timeout, out Reply reply);
        [DllImport(Lib)] public static extern Status hapticd_client_describe_parameter(ClientHandle c, byte[] device, byte[] parameter, double timeout, out ParameterInfo info, out Reply reply);
        [DllImport(Lib)] public static extern Status hapticd_client_emergency_stop(ClientHandle c, byte[] target, double timeout, out Reply reply);
        [DllImport(Lib)] public static extern Status hapticd_client_recover(ClientHandle c, byte[] target, double timeout, out Reply reply);
        [DllImport(Lib)] public static extern Status hapticd_client_operator_command(ClientHandle c, byte[] device, byte[] command, double[] values, int count, double timeout, out Reply reply);
        // the session's haptic scene (texts as Text.Name makes them: UTF-8, zero-terminated)
        [DllImport(Lib)] public static extern Status hapticd_client_scene_claim(ClientHandle c, double timeout, out Reply reply);
        [DllImport(Lib)] public static extern Status hapticd_client_scene_release(ClientHandle c, double timeout, out Reply reply);
        [DllImport(Lib)] public static extern Status hapticd_client_scene_add(ClientHandle c, byte[] obj, double timeout, out Reply reply);
        [DllImport(Lib)] public static extern Status hapticd_client_scene_add_mesh(ClientHandle c, byte[] obj, double[] vertices, long vertexCount, uint[] triangles, long triangleCount, double timeout, out Reply reply);
        [DllImport(Lib)] public static extern Status hapticd_client_scene_remove(ClientHandle c, byte[] obj, double timeout, out Reply reply);
        [DllImport(Lib)] public static extern Status hapticd_client_scene_set_material(ClientHandle c, byte[] obj, byte[] material, double timeout, out Reply reply);
        [DllImport(Lib)] public static extern Status hapticd_client_scene_move(ClientHandle c, byte[] obj, ref Pose pose);
        [DllImport(Lib)] public static extern Status hapticd_client_scene_refused_moves(ClientHandle c, out ulong count, byte[] last, int capacity);
        [DllImport(Lib)] public static extern Status hapticd_client_scene_objects(ClientHandle c, [Out] SceneObject[] output, int capacity, out int count, double timeout, out Reply reply);
        [DllImport(Lib)] public static extern Status hapticd_client_scene_contacts(ClientHandle c, [Out] SceneContact[] output, int capacity, out int count, double timeout, out Reply reply);
        // engine commands
        [DllImport(Lib)] public static extern Status hapticd_client_send(ClientHandle c, byte[] device, ref Command command);
        [DllImport(Lib)] public static extern Status hapticd_client_send_coupling(ClientHandle c, byte[] device, ref Pose proxy, ref Twist twist, ulong serial);
        [DllImport(Lib)] public static extern Status hapticd_client_send_wrench(ClientHandle c, byte[] device, ref Wrench wrench, ref LocalModel model, ulong serial);
        [DllImport(Lib, EntryPoint = "hapticd_client_send_wrench")] public static extern Status hapticd_client_send_wrench_alone(ClientHandle c, byte[] device, ref Wrench wrench, IntPtr noModel, ulong serial);
        [DllImport(Lib)] public static extern Status hapticd_client_send_motion(ClientHandle c, byte[] device, ref Pose pose, ref Twist twist, ulong serial);
        [DllImport(Lib)] public static extern Status hapticd_client_send_group(ClientHandle c, byte[] group, [In] Command[] commands, int count);
        // the engine helper
        [DllImport(Lib)] public static extern Status hapticd_engine_create(ClientHandle c, ref EngineOptions options, out IntPtr engine);
        [DllImport(Lib)] public static extern void hapticd_engine_destroy(IntPtr engine);
        [DllImport(Lib)] public static extern Status hapticd_engine_connect(IntPtr engine);
        [DllImport(Lib)] public static extern Status hapticd_engine_device_count(IntPtr engine, out int count);
        [DllImport(Lib)] public static extern Status hapticd_engine_device(IntPtr engine, int index, out DeviceInfo info);
        [DllImport(Lib)] public static extern Status hapticd_engine_on_claim(IntPtr engine, EngineClaimHook hook, IntPtr user);
        [DllImport(Lib)] public static extern Status hapticd_engine_on_chores(IntPtr engine, EngineChoresHook hook, IntPtr user);
        [DllImport(Lib)] public static extern Status hapticd_engine_on_parameter(IntPtr engine, EngineParameterHook hook, IntPtr user);
        [DllImport(Lib)] public static extern Status hapticd_engine_run(IntPtr engine, EngineAnswer answer, IntPtr user, out EngineEnd end);
        [DllImport(Lib)] public static extern Status hapticd_engine_stop(IntPtr engine);
        [DllImport(Lib)] public static extern Status hapticd_engine_answered(IntPtr engine, out ulong answered);
    }

    // The C client's handle: destroyed once, when disposed or finalised.
    public sealed class ClientHandle : SafeHandle
    {
        public ClientHandle() : base(IntPtr.Zero, true) { }
        public override bool IsInvalid { get { return handle == IntPtr.Zero; } }
        protected override bool ReleaseHandle() { Native.hapticd_client_destroy(handle); return true; }
    }
}
