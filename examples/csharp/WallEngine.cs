// A wall engine in C# on the installed bindings (docs/engines.md, "C# and Unity"): claims a device and answers
// each of its states with a wrench and a local model - a spring of 2000 N/m and a damper of 10 N s/m along x,
// anchored on a wall 2 cm ahead of where the handle started, while the handle is past the wall; nothing while it
// is in front. The server applies the local model every cycle until the next command, so the wall is as stiff at
// the loop's rate as at this program's. Usage: mono wall_engine.exe DEVICE SECONDS [DOMAIN]
using System;
using System.Threading;
using Hapticd;

static class WallEngine
{
    static int Main(string[] args)
    {
        if (args.Length < 2) { Console.Error.WriteLine("usage: wall_engine.exe DEVICE SECONDS [DOMAIN]"); return 2; }
        string device = args[0];
        double seconds = double.Parse(args[1]);
        int domain = args.Length > 2 ? int.Parse(args[2]) : 0;
        using (var client = new Client("cs-wall", domain))
        {
            double deepest = 0.0;
            Engine engine = null;
            // Runs on the DDS receive thread once the device is claimed (its start pose is known by then).
            engine = new Engine(client, device, (ref DeviceState s, ref Command c) => {
                double wallX = engine.StartPose.position.x + 0.02;
                double depth = s.pose.position.x - wallX;
                if (depth > deepest) deepest = depth;
                var anchor = s.pose;
                anchor.position.x = wallX;
                var k = depth > 0 ? new Vec3(2000, 0, 0) : new Vec3();
                var b = depth > 0 ? new Vec3(10, 0, 0) : new Vec3();
                c = Command.Force(new Wrench(), LocalModel.Spring(anchor, k, b), 0);  // the helper sets the serial
            }, 20.0, "cs-wall");
            engine.Start();  // its own thread: finds, claims, answers, retakes a lost claim
            if (!engine.WaitUntilClaimed(20.0))
            {
                Console.Error.WriteLine("cs-wall: " + engine.EndReason + ": " + engine.EndMessage);
                return engine.ExitCode != 0 ? engine.ExitCode : 1;
            }
            Console.WriteLine("cs-wall: claimed '" + device + "'; a wall at x = " +
                              (engine.StartPose.position.x + 0.02).ToString("0.0000") + " m");
            Thread.Sleep(TimeSpan.FromSeconds(seconds));
            engine.Stop();
            Console.WriteLine("cs-wall: answered " + engine.Answered + " states; deepest " +
                              (deepest * 1000).ToString("0.0") + " mm past the wall");
            return engine.Answered > 0 ? 0 : 1;
        }
    }
}
