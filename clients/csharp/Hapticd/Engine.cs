// The engine helper: claims a device and answers each of its states with the command a render function makes,
// from the DDS receive thread (no thread hop, no managed allocation per state). A claim the server ends (the
// application stalled beyond the server's claim hold) is told: ClaimLost turns true; call Reclaim() (or stop).
using System;
using System.Threading;

namespace Hapticd
{
    // Fills `command` for `state` (a coupling's proxy, a wrench, a motion); called on the DDS receive thread, once
    // per state: be quick, do not wait, allocate nothing if the engine is to make no garbage.
    public delegate void Render(ref DeviceState state, ref Command command);

    public sealed class Engine : IDisposable
    {
        readonly Client client_;
        readonly DeviceName device_;
        readonly Render render_;
        readonly StateCallback onState_;         // kept: the C API holds it
        readonly ClaimLostCallback onClaimLost_;
        long answered_;
        int claimLost_;
        int renderErrors_;
        bool started_;

        public Engine(Client client, string device, Render render)
        {
            client_ = client;
            device_ = new DeviceName(device);
            render_ = render;
            unsafe { onState_ = OnState; }
            onClaimLost_ = OnClaimLost;
        }

        public string Device { get { return device_.Text; } }
        public long Answered { get { return Interlocked.Read(ref answered_); } }
        // The server ended this engine's claim (once per claim); Reclaim() claims again.
        public bool ClaimLost { get { return Volatile.Read(ref claimLost_) != 0; } }
        // States the render function threw on (answered with nothing).
        public int RenderErrors { get { return Volatile.Read(ref renderErrors_); } }

        // Claims the device and answers its states from now on. HapticdException when the claim is refused.
        public void Start(double timeoutS = 5.0)
        {
            client_.Claim(device_.Text, timeoutS);
            Client.Check(Native.hapticd_on_claim_lost(client_.Handle, onClaimLost_, IntPtr.Zero));
            Client.Check(Native.hapticd_on_state(client_.Handle, onState_, IntPtr.Zero));
            started_ = true;
        }

        // Claims again after a loss; false (with the reason in `why`) when another client holds the device.
        public bool Reclaim(out string why, double timeoutS = 5.0)
        {
            Interlocked.Exchange(ref claimLost_, 0);
            try
            {
                client_.Claim(device_.Text, timeoutS);
                why = "";
                return true;
            }
            catch (HapticdException e)
            {
                why = e.Message;
                return false;
            }
        }

        // Stops answering and releases the device (its forces fade out).
        public void Stop(double timeoutS = 1.0)
        {
            if (!started_) return;
            started_ = false;
            Native.hapticd_on_state(client_.Handle, null, IntPtr.Zero);
            Native.hapticd_on_claim_lost(client_.Handle, null, IntPtr.Zero);
            try { client_.Release(device_.Text, timeoutS); } catch (HapticdException) { }
        }

        public void Dispose() { Stop(); }

        unsafe void OnState(DeviceState* s, IntPtr user)
        {
            byte* name = s->device;
            byte[] mine = device_.Bytes;
            for (int i = 0; i < mine.Length; ++i)
                if (name[i] != mine[i]) return;  // another device's state
            var command = new Command();
            try
            {
                render_(ref *s, ref command);
            }
            catch (Exception)
            {
                Interlocked.Increment(ref renderErrors_);
                return;  // never into the native caller
            }
            if (command.state_serial == 0) command.state_serial = s->serial;
            if (Native.hapticd_send(client_.Handle, mine, ref command) == Status.Ok) Interlocked.Increment(ref answered_);
        }

        void OnClaimLost(IntPtr device, IntPtr reason, IntPtr user) { Interlocked.Exchange(ref claimLost_, 1); }
    }
}
