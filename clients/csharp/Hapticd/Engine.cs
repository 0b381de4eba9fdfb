// The engine helper for C#: the C API's hapticd_engine_* (the C++ library's one helper) run on a thread of its own,
// so the caller - Unity's main thread - never waits: it finds the device and waits until it started, claims it,
// answers each state with the command a render function makes on the DDS receive thread (no thread hop, no managed
// allocation per state), claims again when the server ended the claim, and ends on Stop(), the session's end or a
// lost device, releasing it. Only static methods marked [MonoPInvokeCallback] are handed to native code (IL2CPP
// marshals no instance delegate); this engine comes back to them as a GCHandle.
using System;
using System.Runtime.InteropServices;
using System.Threading;

namespace Hapticd
{
    // Fills `command` for `state` (a coupling's proxy, a wrench, a motion; the state's serial is set for you); called
    // on the DDS receive thread, once per state: be quick, do not wait, allocate nothing if the engine is to make no
    // garbage. An exception answers the state with nothing (counted in RenderErrors).
    public delegate void Render(ref DeviceState state, ref Command command);

    public sealed unsafe class Engine : IDisposable
    {
        static readonly EngineAnswer AnswerCallback = OnAnswer;
        static readonly EngineClaimHook ClaimCallback = OnClaim;
        static readonly EngineParameterHook ParameterCallback = OnParameter;
        static readonly EngineChoresHook ChoresCallback = OnChores;

        readonly Client client_;
        readonly string device_, name_;
        readonly double waitS_;
        readonly Render render_;
        readonly object lock_ = new object();
        GCHandle self_;  // what native code hands back to the static callbacks; freed by the run's thread at its end
        IntPtr native_;  // under lock_: made, stopped and destroyed by the run's thread
        Thread thread_;
        bool stopRequested_;
        int claimed_, renderErrors_, ended_;
        long answered_;  // the count once the native engine is gone
        DeviceInfo deviceInfo_;
        EngineEnd end_;
        string endMessage_ = "";

        // name: the prefix of the helper's messages on standard output and error.
        public Engine(Client client, string device, Render render, double waitS = 20.0, string name = "cs-engine")
        {
            client_ = client;
            device_ = device;
            render_ = render;
            waitS_ = waitS;
            name_ = name;
        }

        public string Device { get { return device_; } }
        // Claimed (and set up) at least once; the start pose is known from then on.
        public bool Claimed { get { return Volatile.Read(ref claimed_) != 0; } }
        // The handle's pose at the device's first cycle (valid once Claimed).
        public Pose StartPose { get { return deviceInfo_.start_pose; } }
        public long Answered { get { lock (lock_) return native_ == IntPtr.Zero ? answered_ : AnsweredBy(native_); } }
        static long AnsweredBy(IntPtr engine)
        {
            ulong n;
            return Native.hapticd_engine_answered(engine, out n) == Status.Ok ? (long)n : 0;
        }
        // A parameter of the device was set at run time (EventKind.Parameter: its plugin slot in Code, "name = values"
        // in Message), on the engine's thread as soon as it came: re-read what the render function mirrors. Set before
        // Start.
        public Client.EventHandler ParameterChanged { get; set; }
        // Every 20 ms on the engine's thread; return false to end the run. Set before Start.
        public Func<bool> Chores { get; set; }
        public int RenderErrors { get { return Volatile.Read(ref renderErrors_); } }
        // The run ended (Stop, the session's end, no device, a claim lost to another client); EndReason says why.
        public bool Ended { get { return Volatile.Read(ref ended_) != 0; } }
        public EngineEndReason EndReason { get { return end_.Reason; } }
        public string EndMessage { get { return endMessage_; } }
        // What the shipped engines exit with: 0 finished or stopped, 1 no device, 2 refused or failed, 3 claim lost.
        public int ExitCode { get { return end_.exit_code; } }

        // Starts the engine on a thread of its own and returns at once.
        public void Start()
        {
            if (thread_ != null) throw new InvalidOperationException("an engine starts once");
            self_ = GCHandle.Alloc(this);
            thread_ = new Thread(Run) { IsBackground = true, Name = "hapticd-engine " + device_ };
            thread_.Start();
        }

        // Blocks the caller until the device is claimed or the run ended (false), at most timeoutS. Not for Unity's
        // main thread: poll Claimed there.
        public bool WaitUntilClaimed(double timeoutS)
        {
            var until = DateTime.UtcNow.AddSeconds(timeoutS);
            while (!Claimed && !Ended && DateTime.UtcNow < until) Thread.Sleep(10);
            return Claimed;
        }

        // Ends the run (the device is released; its forces fade out) and waits for its thread, at most timeoutS.
        public void Stop(double timeoutS = 5.0)
        {
            if (thread_ == null) return;
            lock (lock_)
            {
                stopRequested_ = true;
                if (native_ != IntPtr.Zero) Native.hapticd_engine_stop(native_);
            }
            thread_.Join(TimeSpan.FromSeconds(timeoutS));
        }

        public void Dispose() { Stop(); }

        void Run()
        {
            IntPtr name = Marshal.StringToHGlobalAnsi(name_), dev = Marshal.StringToHGlobalAnsi(device_);
            IntPtr made = IntPtr.Zero;
            try
            {
                var options = new EngineOptions { size = (uint)Marshal.SizeOf(typeof(EngineOptions)), name = name, device = dev, wait_s = waitS_ };
                if (Native.hapticd_engine_create(client_.Handle, ref options, out made) != Status.Ok)
                {
                    end_.reason = (int)EngineEndReason.Failed;
                    end_.exit_code = 2;
                    endMessage_ = Client.LastError;
                    return;
                }
                lock (lock_) native_ = made;
                if (Native.hapticd_engine_connect(made) == Status.Ok) Native.hapticd_engine_device(made, 0, out deviceInfo_);
                Native.hapticd_engine_on_claim(made, ClaimCallback, GCHandle.ToIntPtr(self_));
                if (ParameterChanged != null) Native.hapticd_engine_on_parameter(made, ParameterCallback, GCHandle.ToIntPtr(self_));
                if (Chores != null) Native.hapticd_engine_on_chores(made, ChoresCallback, GCHandle.ToIntPtr(self_));
                lock (lock_)
                    if (stopRequested_) Native.hapticd_engine_stop(made);
                Native.hapticd_engine_run(made, AnswerCallback, GCHandle.ToIntPtr(self_), out end_);
                endMessage_ = end_.Message;
            }
            finally
            {
                lock (lock_)
                {
                    if (made != IntPtr.Zero)
                    {
                        answered_ = AnsweredBy(made);
                        Native.hapticd_engine_destroy(made);  // after its run: no callback comes any more
                    }
                    native_ = IntPtr.Zero;
                }
                self_.Free();
                Marshal.FreeHGlobal(name);
                Marshal.FreeHGlobal(dev);
                Volatile.Write(ref ended_, 1);
            }
        }

        [MonoPInvokeCallback(typeof(EngineClaimHook))]
        static int OnClaim(int again, IntPtr user)
        {
            var self = (Engine)GCHandle.FromIntPtr(user).Target;
            Volatile.Write(ref self.claimed_, 1);
            return 1;
        }

        [MonoPInvokeCallback(typeof(EngineParameterHook))]
        static void OnParameter(Event* e, ulong answeredThen, IntPtr user)
        {
            var self = (Engine)GCHandle.FromIntPtr(user).Target;
            try { self.ParameterChanged(ref *e); } catch (Exception) { }  // never into the native caller
        }

        [MonoPInvokeCallback(typeof(EngineChoresHook))]
        static int OnChores(IntPtr user)
        {
            var self = (Engine)GCHandle.FromIntPtr(user).Target;
            try { return self.Chores() ? 1 : 0; } catch (Exception) { return 0; }  // a failing chore ends the run
        }

        [MonoPInvokeCallback(typeof(EngineAnswer))]
        static int OnAnswer(DeviceState* states, int count, Command* commands, IntPtr user)
        {
            var self = (Engine)GCHandle.FromIntPtr(user).Target;
            try
            {
                self.render_(ref states[0], ref commands[0]);
            }
            catch (Exception)
            {
                Interlocked.Increment(ref self.renderErrors_);
                return 0;  // never into the native caller
            }
            return 1;
        }
    }
}
