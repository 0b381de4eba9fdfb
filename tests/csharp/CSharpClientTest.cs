// The C# bindings (clients/csharp) on Debian's Mono, against the C API's library:
//   layout FILE                     every struct's size and the per-cycle structs' field offsets match the C API's
//                                   committed layout (clients/c/abi/hapticd_c.layout)
//   errors DOMAIN                   every error path is a HapticdException with the C API's status and message
//   engine DOMAIN DEVICE SECONDS N  a wall engine (Hapticd.Engine) 2 cm ahead of the handle; the simulated operator
//                                   pushes N newtons; a claim the server ends is taken again; the per-cycle calls
//                                   make no managed garbage; prints where the handle rests
//   callbacks                       every delegate handed to native code is a static [MonoPInvokeCallback] method
//   symbols FILE                    every function the library exports (clients/c/abi/hapticd_c.symbols) is bound,
//                                   and every binding names one it exports
//   scene DOMAIN                    the session's haptic scene (a server on vishard3/dds-scene.yaml): a wall the
//                                   operator pushes, the contacts and the listing, a mesh, refusals as exceptions
// Exit code 0 when every check of the mode holds (each failure is printed).
using System;
using System.Collections.Generic;
using System.IO;
using System.Runtime.InteropServices;
using System.Threading;
using Hapticd;

static class CSharpClientTest
{
    static int failures = 0;
    static void Check(bool ok, string what)
    {
        Console.WriteLine((ok ? "ok: " : "FAIL: ") + what);
        if (!ok) ++failures;
    }
    static Status StatusOf(Action a)
    {
        try { a(); return Status.Ok; }
        catch (HapticdException e) { return e.Status; }
    }

    static int Main(string[] args)
    {
        switch (args.Length > 0 ? args[0] : "")
        {
            case "layout": Layout(args[1]); break;
            case "errors": Errors(int.Parse(args[1])); break;
            case "engine": RunEngine(int.Parse(args[1]), args[2], double.Parse(args[3]), double.Parse(args[4])); break;
            case "callbacks": CheckCallbacks(); break;
            case "symbols": Symbols(args[1]); break;
            case "scene": Scene(int.Parse(args[1])); break;
            default: Console.Error.WriteLine("usage: layout FILE | errors DOMAIN | engine DOMAIN DEVICE SECONDS N | callbacks | symbols FILE | scene DOMAIN"); return 2;
        }
        Console.WriteLine(failures == 0 ? "all checks passed" : failures + " failures");
        return failures == 0 ? 0 : 1;
    }

    static void Layout(string file)
    {
        var types = new Dictionary<string, Type> {
            {"hapticd_vec3", typeof(Vec3)}, {"hapticd_quat", typeof(Quat)}, {"hapticd_pose", typeof(Pose)},
            {"hapticd_twist", typeof(Twist)}, {"hapticd_wrench", typeof(Wrench)}, {"hapticd_loop_summary", typeof(LoopSummary)},
            {"hapticd_device_state", typeof(DeviceState)}, {"hapticd_scheme_info", typeof(SchemeInfo)},
            {"hapticd_device_info", typeof(DeviceInfo)}, {"hapticd_event", typeof(Event)}, {"hapticd_telemetry", typeof(Telemetry)},
            {"hapticd_reply", typeof(Reply)}, {"hapticd_parameter_info", typeof(ParameterInfo)},
            {"hapticd_local_model", typeof(LocalModel)}, {"hapticd_command", typeof(Command)},
            {"hapticd_client_options", typeof(ClientOptions)}, {"hapticd_engine_options", typeof(EngineOptions)},
            {"hapticd_engine_end", typeof(EngineEnd)}, {"hapticd_group_info", typeof(GroupInfo)},
            {"hapticd_group_state", typeof(GroupState)}, {"hapticd_fault_cycle", typeof(CycleRecord)},
            {"hapticd_fault_report", typeof(FaultReport)}, {"hapticd_scene_object", typeof(SceneObject)},
            {"hapticd_scene_contact", typeof(SceneContact)} };
        int checkedCount = 0;
        foreach (var line in File.ReadAllLines(file))
        {
            var f = line.Split(' ');
            if (f[0] == "sizeof" && types.ContainsKey(f[1]))
            {
                int size = Marshal.SizeOf(types[f[1]]);
                Check(size == int.Parse(f[2]), f[1] + ": " + size + " bytes, C " + f[2]);
                ++checkedCount;
            }
            else if (f[0] == "offsetof")
            {
                var parts = f[1].Split('.');
                if (!types.ContainsKey(parts[0])) continue;
                // An array of structs is one field per element in C# (states_0, states_1, ...): its first.
                var type = types[parts[0]];
                string field = type.GetField(parts[1]) != null ? parts[1] : parts[1] + "_0";
                long offset = Marshal.OffsetOf(type, field).ToInt64();
                Check(offset == long.Parse(f[2]), f[1] + " at " + offset + ", C " + f[2]);
                ++checkedCount;
            }
        }
        Check(checkedCount > 40, checkedCount + " sizes and offsets compared");
        Check(Client.ApiVersion == 2, "the library's API version is the bindings' (2)");
    }

    static void Errors(int domain)
    {
        Check(StatusOf(() => new Client("", domain)) == Status.InvalidArgument && Client.LastError.Contains("client id"),
              "an empty client id: InvalidArgument, '" + Client.LastError + "'");
        Check(StatusOf(() => new Client("an-id-that-is-longer-than-thirty-one-characters", domain)) == Status.InvalidArgument,
              "a client id of 47 characters: InvalidArgument");
        Check(StatusOf(() => new Client("cs", 231)) == Status.InvalidArgument, "domain 231: InvalidArgument");
        Check(StatusOf(() => new Client("cs", domain, "interfaces=;bogus")) == Status.InvalidArgument, "a bad network text: InvalidArgument");
        using (var c = new Client("cs-errors", domain))
        {
            Check(StatusOf(() => c.WaitForState("nobody", 0.1)) == Status.Timeout, "no state of 'nobody': Timeout");
            Check(StatusOf(() => c.WaitForState("nobody", -1)) == Status.InvalidArgument, "a negative timeout: InvalidArgument");
            Check(StatusOf(() => c.WaitForState("", 0.1)) == Status.InvalidArgument, "an empty device name: InvalidArgument");
            Check(StatusOf(() => c.Claim("nobody", 0.3)) == Status.Timeout, "a claim nobody answers: Timeout");
            Check(StatusOf(() => c.SetParameter("nobody", "virtual_model.mass_kg", new double[17], 0.1)) == Status.InvalidArgument,
                  "17 values: InvalidArgument");
            DeviceState s;
            Check(!c.TryLatestState(new DeviceName("nobody"), out s), "no latest state of 'nobody': false");
            var bad = new Command { kind = 7 };
            Check(StatusOf(() => c.Send(new DeviceName("nobody"), ref bad)) == Status.InvalidArgument && Client.LastError.Contains("unknown command kind"),
                  "an unknown command kind: InvalidArgument");
            Check(StatusOf(() => c.SendGroup(new DeviceName("g"), new Command[9], 9)) == Status.InvalidArgument, "a group command of 9: InvalidArgument");
            Check(c.Devices().Length == 0, "no devices on an empty domain");
            Check(c.Groups().Length == 0, "no groups on an empty domain");
            Check(StatusOf(() => c.WaitForGroup("nobody", 0.1)) == Status.Timeout, "no group 'nobody': Timeout");
            GroupState g;
            Check(!c.TryLatestGroupState(new DeviceName("nobody"), out g), "no latest group state of 'nobody': false");
            Check(c.LatestFaultReport("nobody") == null, "no fault report of 'nobody': null");
            Check(!c.ClaimLost("nobody"), "no claim of 'nobody' lost");
            Check(StatusOf(() => c.ClaimLost("")) == Status.InvalidArgument, "ClaimLost of an empty name: InvalidArgument (was: false)");
            Check(Client.StatusName(Status.Timeout) == "HAPTICD_ERROR_TIMEOUT", "StatusName(Timeout): " + Client.StatusName(Status.Timeout));
            Check(StatusOf(() => c.OnState(new DeviceName("an-id-that-is-longer-than-thirty-one-characters"), (ref DeviceState st) => { })) == Status.InvalidArgument,
                  "a state filter of 47 characters: InvalidArgument");
            var w = new Wrench();
            var model = LocalModel.Spring(new Pose { orientation = Quat.Identity }, new Vec3(100, 0, 0), new Vec3());
            var p0 = new Pose { orientation = Quat.Identity };
            var t0 = new Twist();
            Check(StatusOf(() => c.SendWrench(new DeviceName("nobody"), ref w, 0)) == Status.Ok, "a wrench is handed over (nobody reads it)");
            Check(StatusOf(() => c.SendWrench(new DeviceName("nobody"), ref w, ref model, 0)) == Status.Ok, "a wrench with its local model is handed over");
            Check(StatusOf(() => c.SendMotion(new DeviceName("nobody"), ref p0, ref t0, 0)) == Status.Ok, "a motion is handed over");
        }
        var disposed = new Client("cs-disposed", domain);
        disposed.Dispose();
        Check(StatusOf(() => { try { disposed.WaitForState("x", 0.1); } catch (ObjectDisposedException) { throw new HapticdException(Status.InvalidArgument, "disposed"); } }) == Status.InvalidArgument,
              "a disposed client: ObjectDisposedException, never a crash");
    }

    static double wallX;

    static void RunEngine(int domain, string device, double seconds, double pushN)
    {
        using (var client = new Client("cs-wall-engine", domain))
        {
            double startX = 0;
            // The engine helper runs on its own thread; its render reads the wall set once the device was found.
            var engine = new Engine(client, device, (ref DeviceState s, ref Command c) => {
                var proxy = s.pose;
                if (proxy.position.x > wallX) proxy.position.x = wallX;
                c = Command.Coupling(proxy, new Twist(), 0);  // the helper sets the state's serial
            }, 20.0, "cs-wall-engine");
            wallX = double.PositiveInfinity;
            engine.Start();
            Check(engine.WaitUntilClaimed(20.0), "claimed: " + engine.EndMessage);
            startX = engine.StartPose.position.x;
            wallX = startX + 0.02;
            Console.WriteLine("cs-wall-engine: claimed '" + device + "'; a wall at x = " + wallX.ToString("+0.0000;-0.0000") + " m");
            if (pushN != 0) client.OperatorCommand(device, "push", new double[] { pushN, 0, 0, 0.2 });

            // The per-cycle calls from this thread: no managed garbage.
            var name = new DeviceName(device);
            DeviceState state;
            var still = new Twist();
            client.TryLatestState(name, out state);
            long before = GC.GetAllocatedBytesForCurrentThread();
            for (int i = 0; i < 2000; ++i)
            {
                client.TryLatestState(name, out state);
                var proxy = state.pose;
                if (proxy.position.x > wallX) proxy.position.x = wallX;
                client.SendCoupling(name, ref proxy, ref still, state.serial);
            }
            long garbage = GC.GetAllocatedBytesForCurrentThread() - before;
            Check(garbage == 0, "2000 state reads and commands made " + garbage + " bytes of managed garbage");

            // A claim the server ends (this process stopped beyond its claim hold) is retaken by the helper.
            var end = DateTime.UtcNow.AddSeconds(seconds);
            while (DateTime.UtcNow < end && !engine.Ended) Thread.Sleep(50);
            Check(!engine.Ended, "the engine ran to the end: " + engine.EndReason + ": " + engine.EndMessage);
            DeviceState last;
            client.TryLatestState(name, out last);
            engine.Stop();
            long answered = engine.Answered;
            Check(engine.Ended && engine.EndReason == EngineEndReason.Stopped && engine.ExitCode == 0,
                  "Stop() ended the run: " + engine.EndReason + " " + engine.EndMessage);
            Check(engine.RenderErrors == 0, "the render function never threw");
            Check(answered > 0, "answered " + answered + " states");
            Console.WriteLine("cs-wall-engine: answered " + answered + " states; handle " +
                              (last.pose.position.x - startX).ToString("0.0000") + " m past the start, the wall at 0.0200 m");
        }
    }

    // Every function of the C API has its binding (step 5 of issue 63: the bindings covered 27 of 37 functions).
    static void Scene(int domain)
    {
        using (var client = new Client("cs-scene-engine", domain))
        using (var other = new Client("cs-scene-other", domain))
        {
            client.WaitForDevice("vishard3", 20.0, true);
            var start = client.WaitForState("vishard3", 10.0).pose.position;
            client.SceneClaim();
            Check(StatusOf(() => other.SceneClaim()) == Status.Refused, "a second engine's claim is refused");
            var inv = System.Globalization.CultureInfo.InvariantCulture;
            string wall = string.Format(inv, "{{\"name\": \"wall\", \"shape\": \"plane\", \"position\": [{0}, {1}, {2}], " +
                "\"normal\": [-1, 0, 0], \"material\": {{\"stiffness\": 3000, \"damping\": 5}}}}", start.x + 0.02, start.y, start.z);
            client.SceneAdd(wall);
            client.OperatorCommand("vishard3", "push", new double[] { 15, 0, 0, 0.3 });
            Thread.Sleep(1500);
            var contacts = other.SceneContacts();
            Check(contacts.Length == 1 && contacts[0].Device == "vishard3" && contacts[0].ObjectName == "wall",
                  contacts.Length + " contacts, the hand's on the wall");
            double held = client.WaitForState("vishard3", 5.0).pose.position.x - start.x;
            double pressed = contacts.Length > 0 ? contacts[0].force.x : 0;
            Console.WriteLine("the wall holds the push: the handle at " + (1e3 * held).ToString("0.00", inv) + " mm, pressing " +
                              pressed.ToString("0.00", inv) + " N");
            Check(pressed > 5 && Math.Abs(held - (0.015 + pressed / 3000)) < 0.001, "the wall's spring holds the hand");
            client.SceneAddMesh("{\"name\": \"shard\", \"shape\": \"mesh\", \"position\": [0.5, 0, 0]}",
                                new double[] { 0, -0.01, -0.01, 0, 0.01, -0.01, 0, 0, 0.01 }, new uint[] { 0, 1, 2 });
            var objects = client.SceneObjects();
            Check(objects.Length == 2 && objects[1].Name == "shard" && objects[1].Shape == "mesh" && objects[1].triangles == 1,
                  "the listing: the wall and the uploaded mesh");
            var refused = StatusOf(() => client.SceneAdd("{\"name\": \"ball\", \"shape\": \"sphere\", \"radius\": -1}"));
            Check(refused == Status.Refused, "a negative radius is refused");
            Check(StatusOf(() => other.SceneRemove("wall")) == Status.Refused, "an intruder's removal is refused");
            var to = new Pose();
            to.orientation.w = 1;
            client.SceneMove("wall", ref to);  // written; refused by the server (the wall is not moving)
            for (int i = 0; i < 500 && client.SceneRefusedMoves() == 0; ++i) Thread.Sleep(10);
            Check(client.SceneRefusedMoves() == 1, "a move of a still object is refused and counted");
            client.SceneRelease();
            Check(StatusOf(() => other.SceneClaim()) == Status.Ok, "released: the other engine claims the scene");
        }
    }

    static void Symbols(string file)
    {
        var exported = new HashSet<string>();
        foreach (var line in File.ReadAllLines(file))
            if (line.Length > 0) exported.Add(line.Split('@')[0]);
        var bound = new HashSet<string>();
        var native = typeof(Client).Assembly.GetType("Hapticd.Native");
        foreach (var m in native.GetMethods(System.Reflection.BindingFlags.Public | System.Reflection.BindingFlags.Static))
        {
            var import = (DllImportAttribute)Attribute.GetCustomAttribute(m, typeof(DllImportAttribute));
            if (import == null) continue;
            bound.Add(string.IsNullOrEmpty(import.EntryPoint) ? m.Name : import.EntryPoint);
        }
        foreach (var f in exported) Check(bound.Contains(f), f + " is bound");
        foreach (var f in bound) Check(exported.Contains(f), f + " is a function the library exports");
        Check(exported.Count > 40, exported.Count + " exported functions");
    }

    // IL2CPP marshals only static methods marked [MonoPInvokeCallback]: every delegate of a native callback type the
    // assembly keeps is one, and no instance field holds such a delegate.
    static void CheckCallbacks()
    {
        var assembly = typeof(Client).Assembly;
        int checkedDelegates = 0;
        foreach (var type in assembly.GetTypes())
        {
            foreach (var field in type.GetFields(System.Reflection.BindingFlags.Static | System.Reflection.BindingFlags.Instance | System.Reflection.BindingFlags.Public | System.Reflection.BindingFlags.NonPublic))
            {
                if (!typeof(Delegate).IsAssignableFrom(field.FieldType)) continue;
                if (field.FieldType.GetCustomAttributes(typeof(UnmanagedFunctionPointerAttribute), false).Length == 0) continue;
                Check(field.IsStatic, type.Name + "." + field.Name + " is a static field (no instance delegate crosses into native code)");
                var d = (Delegate)field.GetValue(null);
                Check(d != null && d.Method.IsStatic, type.Name + "." + field.Name + " holds a static method");
                Check(d.Method.GetCustomAttributes(typeof(MonoPInvokeCallbackAttribute), false).Length == 1,
                      d.Method.Name + " is marked [MonoPInvokeCallback]");
                ++checkedDelegates;
            }
        }
        Check(checkedDelegates >= 2, checkedDelegates + " native callbacks checked");
    }
}
