// A hapticd client for C# (Unity on Mono or IL2CPP, any .NET): the C API (Native.cs) behind a SafeHandle, its
// errors as HapticdException (with the C API's status and message), names turned into the C API's form once.
// Threads: as the C API's (hapticd/client.h) - any thread; waiting calls block; the state callback runs on the
// DDS receive thread. Per cycle (a state read, a command sent) nothing is allocated on the managed heap: use the
// DeviceName overloads (a device's name encoded once) and the struct-returning calls.
using System;
using System.Runtime.InteropServices;

namespace Hapticd
{
    public sealed class HapticdException : Exception
    {
        public Status Status { get; private set; }
        public HapticdException(Status status, string message) : base(message) { Status = status; }
    }

    // A device's or group's name as the C API takes it (zero-terminated UTF-8), made once per name.
    public sealed class DeviceName
    {
        internal readonly byte[] Bytes;
        public readonly string Text;
        public DeviceName(string text) { Text = text; Bytes = Hapticd.Text.Name(text); }
        public override string ToString() { return Text; }
    }

    public sealed unsafe class Client : IDisposable
    {
        readonly ClientHandle handle_;
        public string Id { get; private set; }

        // domain: the DDS domain; network: null for loopback only (or HAPTICD_DDS_NETWORK / HAPTICD_DDS_CONFIG).
        public Client(string id, int domain = 0, string network = null, string cycloneConfig = null)
        {
            var options = new ClientOptions { size = (uint)Marshal.SizeOf(typeof(ClientOptions)), domain_id = domain };
            options.client_id = Marshal.StringToHGlobalAnsi(id ?? "");
            options.network = network == null ? IntPtr.Zero : Marshal.StringToHGlobalAnsi(network);
            options.cyclone_config = cycloneConfig == null ? IntPtr.Zero : Marshal.StringToHGlobalAnsi(cycloneConfig);
            try
            {
                ClientHandle h;
                var status = Native.hapticd_client_create(ref options, out h);
                if (status != Status.Ok)
                {
                    var message = LastError;
                    h.Dispose();
                    throw new HapticdException(status, message);
                }
                handle_ = h;
                Id = id;
            }
            finally
            {
                Marshal.FreeHGlobal(options.client_id);
                if (options.network != IntPtr.Zero) Marshal.FreeHGlobal(options.network);
                if (options.cyclone_config != IntPtr.Zero) Marshal.FreeHGlobal(options.cyclone_config);
            }
        }

        public static int ApiVersion { get { return Native.hapticd_api_version(); } }
        public static string LastError { get { return Marshal.PtrToStringAnsi(Native.hapticd_last_error()) ?? ""; } }
        // A status's name ("HAPTICD_ERROR_TIMEOUT").
        public static string StatusName(Status status) { return Marshal.PtrToStringAnsi(Native.hapticd_status_name(status)) ?? ""; }

        internal static void Check(Status s)
        {
            if (s != Status.Ok) throw new HapticdException(s, LastError);
        }
        internal ClientHandle Handle { get { return handle_; } }

        // ---- devices ----
        public DeviceInfo WaitForDevice(string device, double timeoutS, bool started = false)
        {
            DeviceInfo info;
            Check(Native.hapticd_client_wait_for_device(handle_, Text.Name(device), timeoutS, started ? 1 : 0, out info));
            return info;
        }
        public DeviceInfo[] Devices()
        {
            int count;
            Check(Native.hapticd_client_list_devices(handle_, null, 0, out count));
            var all = new DeviceInfo[count];
            Check(Native.hapticd_client_list_devices(handle_, all, count, out count));
            return all;
        }
        // The newest state; false before the first. Per cycle: no managed allocation.
        public bool TryLatestState(DeviceName device, out DeviceState state)
        {
            var s = Native.hapticd_client_latest_state(handle_, device.Bytes, out state);
            if (s == Status.NotFound) return false;
            Check(s);
            return true;
        }
        public DeviceState WaitForState(string device, double timeoutS, ulong after = 0)
        {
            DeviceState state;
            Check(Native.hapticd_client_wait_for_state(handle_, Text.Name(device), timeoutS, after, out state));
            return state;
        }
        // ---- groups (session file `groups`) ----
        public GroupInfo[] Groups()
        {
            int count;
            Check(Native.hapticd_client_list_groups(handle_, null, 0, out count));
            var all = new GroupInfo[count];
            Check(Native.hapticd_client_list_groups(handle_, all, count, out count));
            return all;
        }
        public GroupInfo WaitForGroup(string group, double timeoutS)
        {
            GroupInfo info;
            Check(Native.hapticd_client_wait_for_group(handle_, Text.Name(group), timeoutS, out info));
            return info;
        }
        // The newest states of every device of the group from one cycle; false before the first. No managed allocation.
        public bool TryLatestGroupState(DeviceName group, out GroupState state)
        {
            var s = Native.hapticd_client_latest_group_state(handle_, group.Bytes, out state);
            if (s == Status.NotFound) return false;
            Check(s);
            return true;
        }
        public GroupState WaitForGroupState(string group, double timeoutS, ulong after = 0)
        {
            GroupState state;
            Check(Native.hapticd_client_wait_for_group_state(handle_, Text.Name(group), timeoutS, after, out state));
            return state;
        }

        public Telemetry? LatestTelemetry(string device)
        {
            Telemetry t;
            var s = Native.hapticd_client_latest_telemetry(handle_, Text.Name(device), out t);
            if (s == Status.NotFound) return null;
            Check(s);
            return t;
        }
        // The newest fault report of the device (the fault and the cycles before it); null before the first.
        public FaultReport? LatestFaultReport(string device)
        {
            FaultReport r;
            var s = Native.hapticd_client_latest_fault_report(handle_, Text.Name(device), out r);
            if (s == Status.NotFound) return null;
            Check(s);
            return r;
        }
        public Event[] TakeEvents(int capacity = 64)
        {
            var events = new Event[capacity];
            int count;
            Check(Native.hapticd_client_take_events(handle_, events, capacity, out count));
            Array.Resize(ref events, count);
            return events;
        }

        // ---- callbacks: on the library's threads (states: the DDS receive thread), one at a time; null removes. Only
        // static [MonoPInvokeCallback] methods are handed to native code; this client comes back to them through a
        // GCHandle (freed when the client is disposed). ----
        public delegate void StateHandler(ref DeviceState state);
        public delegate void EventHandler(ref Event e);
        public delegate void ClaimLostHandler(string device, string reason);
        static readonly StateCallback StateCallbackStatic = OnNativeState;
        static readonly EventCallback EventCallbackStatic = OnNativeEvent;
        static readonly ClaimLostCallback ClaimLostCallbackStatic = OnNativeClaimLost;
        GCHandle self_;
        StateHandler onState_;
        EventHandler onEvent_;
        ClaimLostHandler onClaimLost_;
        IntPtr Self()
        {
            if (!self_.IsAllocated) self_ = GCHandle.Alloc(this, GCHandleType.Weak);
            return GCHandle.ToIntPtr(self_);
        }
        // Every state of `device` (null: of every device).
        public void OnState(DeviceName device, StateHandler handler)
        {
            onState_ = handler;
            Check(handler == null ? Native.hapticd_client_on_state(handle_, null, null, IntPtr.Zero)
                                  : Native.hapticd_client_on_state(handle_, device == null ? null : device.Bytes, StateCallbackStatic, Self()));
        }
        // Every event (they are also kept for TakeEvents).
        public void OnEvent(EventHandler handler)
        {
            onEvent_ = handler;
            Check(handler == null ? Native.hapticd_client_on_event(handle_, null, IntPtr.Zero)
                                  : Native.hapticd_client_on_event(handle_, EventCallbackStatic, Self()));
        }
        // A claim of this client ended without its release (the server handed the device on or freed it).
        public void OnClaimLost(ClaimLostHandler handler)
        {
            onClaimLost_ = handler;
            Check(handler == null ? Native.hapticd_client_on_claim_lost(handle_, null, IntPtr.Zero)
                                  : Native.hapticd_client_on_claim_lost(handle_, ClaimLostCallbackStatic, Self()));
        }
        static Client Of(IntPtr user) { return GCHandle.FromIntPtr(user).Target as Client; }
        [MonoPInvokeCallback(typeof(StateCallback))]
        static unsafe void OnNativeState(DeviceState* state, IntPtr user)
        {
            var self = Of(user);
            var handler = self == null ? null : self.onState_;
            if (handler == null) return;
            try { handler(ref *state); } catch (Exception) { }  // never into the native caller
        }
        [MonoPInvokeCallback(typeof(EventCallback))]
        static unsafe void OnNativeEvent(Event* e, IntPtr user)
        {
            var self = Of(user);
            var handler = self == null ? null : self.onEvent_;
            if (handler == null) return;
            try { handler(ref *e); } catch (Exception) { }
        }
        [MonoPInvokeCallback(typeof(ClaimLostCallback))]
        static void OnNativeClaimLost(IntPtr device, IntPtr reason, IntPtr user)
        {
            var self = Of(user);
            var handler = self == null ? null : self.onClaimLost_;
            if (handler == null) return;
            try { handler(Marshal.PtrToStringAnsi(device) ?? "", Marshal.PtrToStringAnsi(reason) ?? ""); } catch (Exception) { }
        }

        // ---- requests: the reply when accepted; HapticdException (Refused, Timeout, ...) otherwise. A target of Claim,
        // Release, EmergencyStop and Recover is a device or a group (all its devices at once; "*": every device). ----
        public Reply Claim(string target, double timeoutS = 2.0) { return Request((out Reply r) => Native.hapticd_client_claim(handle_, Text.Name(target), timeoutS, out r)); }
        public Reply Release(string target, double timeoutS = 2.0) { return Request((out Reply r) => Native.hapticd_client_release(handle_, Text.Name(target), timeoutS, out r)); }
        public Reply SwitchScheme(string device, string scheme, double timeoutS = 2.0) { return Request((out Reply r) => Native.hapticd_client_switch_scheme(handle_, Text.Name(device), Text.Name(scheme), timeoutS, out r)); }
        public Reply SetParameter(string device, string parameter, double[] values, double timeoutS = 2.0) { return Request((out Reply r) => Native.hapticd_client_set_parameter(handle_, Text.Name(device), Text.Name(parameter), values, values == null ? 0 : values.Length, timeoutS, out r)); }
        public Reply GetParameter(string device, string parameter, double timeoutS = 2.0) { return Request((out Reply r) => Native.hapticd_client_get_parameter(handle_, Text.Name(device), Text.Name(parameter), timeoutS, out r)); }
        public ParameterInfo DescribeParameter(string device, string parameter, double timeoutS = 2.0)
        {
            ParameterInfo info;
            Reply reply;
            Check(Native.hapticd_client_describe_parameter(handle_, Text.Name(device), Text.Name(parameter), timeoutS, out info, out reply));
            return info;
        }
        public Reply EmergencyStop(string target, double timeoutS = 2.0) { return Request((out Reply r) => Native.hapticd_client_emergency_stop(handle_, Text.Name(target), timeoutS, out r)); }
        public Reply Recover(string target, double timeoutS = 2.0) { return Request((out Reply r) => Native.hapticd_client_recover(handle_, Text.Name(target), timeoutS, out r)); }
        // Simulated devices: "push" {fx, fy, fz[, ramp_s]}, "move" {dx, dy, dz[, duration_s]}, "grasp" {g}, "release".
        public Reply OperatorCommand(string device, string command, double[] values, double timeoutS = 2.0) { return Request((out Reply r) => Native.hapticd_client_operator_command(handle_, Text.Name(device), Text.Name(command), values, values == null ? 0 : values.Length, timeoutS, out r)); }
        // Whether the newest claim of the device (or group) was ended by the server.
        public bool ClaimLost(string device)
        {
            int lost;
            Check(Native.hapticd_client_claim_lost(handle_, Text.Name(device), out lost));
            return lost != 0;
        }

        // ---- the session's haptic scene (docs/haptic-scene.md): claim it, edit it at the engine's frame rate (objects
        // and materials as JSON, as the scene file writes them), ask what the hands do to it. A refusal throws. ----
        public Reply SceneClaim(double timeoutS = 2.0) { return Request((out Reply r) => Native.hapticd_client_scene_claim(handle_, timeoutS, out r)); }
        public Reply SceneRelease(double timeoutS = 2.0) { return Request((out Reply r) => Native.hapticd_client_scene_release(handle_, timeoutS, out r)); }
        public Reply SceneAdd(string objectJson, double timeoutS = 2.0) { return Request((out Reply r) => Native.hapticd_client_scene_add(handle_, Text.Name(objectJson), timeoutS, out r)); }
        // vertices: x, y, z of each (m, the object's frame); triangles: three indices each.
        public Reply SceneAddMesh(string objectJson, double[] vertices, uint[] triangles, double timeoutS = 10.0)
        {
            return Request((out Reply r) => Native.hapticd_client_scene_add_mesh(handle_, Text.Name(objectJson), vertices, vertices.Length / 3, triangles, triangles.Length / 3, timeoutS, out r));
        }
        public Reply SceneRemove(string name, double timeoutS = 2.0) { return Request((out Reply r) => Native.hapticd_client_scene_remove(handle_, Text.Name(name), timeoutS, out r)); }
        public Reply SceneSetMaterial(string name, string material, double timeoutS = 2.0) { return Request((out Reply r) => Native.hapticd_client_scene_set_material(handle_, Text.Name(name), Text.Name(material), timeoutS, out r)); }
        // A moving object's new pose, at the engine's frame rate (not waited for; refusals: SceneRefusedMoves).
        public void SceneMove(string name, ref Pose pose) { Check(Native.hapticd_client_scene_move(handle_, Text.Name(name), ref pose)); }
        public ulong SceneRefusedMoves()
        {
            ulong count;
            Check(Native.hapticd_client_scene_refused_moves(handle_, out count, null, 0));
            return count;
        }
        public SceneObject[] SceneObjects(double timeoutS = 2.0)
        {
            Reply reply;
            int count;
            Check(Native.hapticd_client_scene_objects(handle_, null, 0, out count, timeoutS, out reply));
            var all = new SceneObject[count];
            Check(Native.hapticd_client_scene_objects(handle_, all, count, out count, timeoutS, out reply));
            if (count < all.Length) Array.Resize(ref all, count);
            return all;
        }
        public SceneContact[] SceneContacts(double timeoutS = 2.0)
        {
            Reply reply;
            int count;
            Check(Native.hapticd_client_scene_contacts(handle_, null, 0, out count, timeoutS, out reply));
            var all = new SceneContact[count];
            Check(Native.hapticd_client_scene_contacts(handle_, all, count, out count, timeoutS, out reply));
            if (count < all.Length) Array.Resize(ref all, count);
            return all;
        }

        delegate Status RequestCall(out Reply reply);
        static Reply Request(RequestCall call)
        {
            Reply reply;
            Check(call(out reply));
            return reply;
        }

        // ---- engine commands: per cycle, no managed allocation ----
        public void Send(DeviceName device, ref Command command) { Check(Native.hapticd_client_send(handle_, device.Bytes, ref command)); }
        public void SendCoupling(DeviceName device, ref Pose proxy, ref Twist twist, ulong stateSerial)
        {
            Check(Native.hapticd_client_send_coupling(handle_, device.Bytes, ref proxy, ref twist, stateSerial));
        }
        public void SendWrench(DeviceName device, ref Wrench wrench, ulong stateSerial)
        {
            Check(Native.hapticd_client_send_wrench_alone(handle_, device.Bytes, ref wrench, IntPtr.Zero, stateSerial));
        }
        // A wrench with its local model (LocalModel.Spring): applied by the server every cycle until the next command.
        public void SendWrench(DeviceName device, ref Wrench wrench, ref LocalModel model, ulong stateSerial)
        {
            Check(Native.hapticd_client_send_wrench(handle_, device.Bytes, ref wrench, ref model, stateSerial));
        }
        public void SendMotion(DeviceName device, ref Pose pose, ref Twist twist, ulong stateSerial)
        {
            Check(Native.hapticd_client_send_motion(handle_, device.Bytes, ref pose, ref twist, stateSerial));
        }
        // One command per device of the group (each naming its device), in the group's order.
        public void SendGroup(DeviceName group, Command[] commands, int count)
        {
            Check(Native.hapticd_client_send_group(handle_, group.Bytes, commands, count));
        }

        public void Dispose()
        {
            handle_.Dispose();  // no callback comes after the client is destroyed
            if (self_.IsAllocated) self_.Free();
        }
    }
}
