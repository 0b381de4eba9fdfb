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

    public sealed class Client : IDisposable
    {
        readonly ClientHandle handle_;
        public string Id { get; private set; }

        // domain: the DDS domain; network: null for loopback only (or HAPTICD_DDS_NETWORK / HAPTICD_DDS_CONFIG).
        public Client(string id, int domain = 0, string network = null, string cycloneConfig = null)
        {
            var options = new ClientOptions { domain_id = domain };
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

        internal static void Check(Status s)
        {
            if (s != Status.Ok) throw new HapticdException(s, LastError);
        }
        internal ClientHandle Handle { get { return handle_; } }

        // ---- devices ----
        public DeviceInfo WaitForDevice(string device, double timeoutS, bool started = false)
        {
            DeviceInfo info;
            Check(Native.hapticd_wait_for_device(handle_, Text.Name(device), timeoutS, started ? 1 : 0, out info));
            return info;
        }
        public DeviceInfo[] Devices()
        {
            int count;
            Check(Native.hapticd_list_devices(handle_, null, 0, out count));
            var all = new DeviceInfo[count];
            Check(Native.hapticd_list_devices(handle_, all, count, out count));
            return all;
        }
        // The newest state; false before the first. Per cycle: no managed allocation.
        public bool TryLatestState(DeviceName device, out DeviceState state)
        {
            var s = Native.hapticd_latest_state(handle_, device.Bytes, out state);
            if (s == Status.NotFound) return false;
            Check(s);
            return true;
        }
        public DeviceState WaitForState(string device, double timeoutS, ulong after = 0)
        {
            DeviceState state;
            Check(Native.hapticd_wait_for_state(handle_, Text.Name(device), timeoutS, after, out state));
            return state;
        }
        public Telemetry? LatestTelemetry(string device)
        {
            Telemetry t;
            var s = Native.hapticd_latest_telemetry(handle_, Text.Name(device), out t);
            if (s == Status.NotFound) return null;
            Check(s);
            return t;
        }
        public Event[] TakeEvents(int capacity = 64)
        {
            var events = new Event[capacity];
            int count;
            Check(Native.hapticd_take_events(handle_, events, capacity, out count));
            Array.Resize(ref events, count);
            return events;
        }

        // ---- requests: the reply when accepted; HapticdException (Refused, Timeout, ...) otherwise ----
        public Reply Claim(string device, double timeoutS = 2.0) { return Request((out Reply r) => Native.hapticd_claim(handle_, Text.Name(device), timeoutS, out r)); }
        public Reply Release(string device, double timeoutS = 2.0) { return Request((out Reply r) => Native.hapticd_release(handle_, Text.Name(device), timeoutS, out r)); }
        public Reply SwitchScheme(string device, string scheme, double timeoutS = 2.0) { return Request((out Reply r) => Native.hapticd_switch_scheme(handle_, Text.Name(device), Text.Name(scheme), timeoutS, out r)); }
        public Reply SetParameter(string device, string parameter, double[] values, double timeoutS = 2.0) { return Request((out Reply r) => Native.hapticd_set_parameter(handle_, Text.Name(device), Text.Name(parameter), values, values == null ? 0 : values.Length, timeoutS, out r)); }
        public Reply GetParameter(string device, string parameter, double timeoutS = 2.0) { return Request((out Reply r) => Native.hapticd_get_parameter(handle_, Text.Name(device), Text.Name(parameter), timeoutS, out r)); }
        public ParameterInfo DescribeParameter(string device, string parameter, double timeoutS = 2.0)
        {
            ParameterInfo info;
            Reply reply;
            Check(Native.hapticd_describe_parameter(handle_, Text.Name(device), Text.Name(parameter), timeoutS, out info, out reply));
            return info;
        }
        public Reply EmergencyStop(string device, double timeoutS = 2.0) { return Request((out Reply r) => Native.hapticd_emergency_stop(handle_, Text.Name(device), timeoutS, out r)); }
        public Reply Recover(string device, double timeoutS = 2.0) { return Request((out Reply r) => Native.hapticd_recover(handle_, Text.Name(device), timeoutS, out r)); }
        // Simulated devices: "push" {fx, fy, fz[, ramp_s]}, "move" {dx, dy, dz[, duration_s]}, "grasp" {g}, "release".
        public Reply OperatorCommand(string device, string command, double[] values, double timeoutS = 2.0) { return Request((out Reply r) => Native.hapticd_operator_command(handle_, Text.Name(device), Text.Name(command), values, values == null ? 0 : values.Length, timeoutS, out r)); }
        public Reply ClaimGroup(string group, double timeoutS = 2.0) { return Request((out Reply r) => Native.hapticd_claim_group(handle_, Text.Name(group), timeoutS, out r)); }
        public Reply ReleaseGroup(string group, double timeoutS = 2.0) { return Request((out Reply r) => Native.hapticd_release_group(handle_, Text.Name(group), timeoutS, out r)); }
        // Whether the newest claim of the device was ended by the server (see Engine.ClaimLost).
        public bool ClaimLost(string device) { return Native.hapticd_claim_lost(handle_, Text.Name(device)) != 0; }

        delegate Status RequestCall(out Reply reply);
        static Reply Request(RequestCall call)
        {
            Reply reply;
            Check(call(out reply));
            return reply;
        }

        // ---- engine commands: per cycle, no managed allocation ----
        public void Send(DeviceName device, ref Command command) { Check(Native.hapticd_send(handle_, device.Bytes, ref command)); }
        public void SendCoupling(DeviceName device, ref Pose proxy, ref Twist twist, ulong stateSerial)
        {
            Check(Native.hapticd_send_coupling(handle_, device.Bytes, ref proxy, ref twist, stateSerial));
        }
        // One command per device of the group (each naming its device: SetDevice), in the group's order.
        public void SendGroup(DeviceName group, Command[] commands, int count)
        {
            Check(Native.hapticd_send_group(handle_, group.Bytes, commands, count));
        }

        public void Dispose() { handle_.Dispose(); }
    }
}
