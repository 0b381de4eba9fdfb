#!/usr/bin/python3
"""A rendering engine in Python: a wall normal to x, 2 cm ahead of the handle's start, rendered over DDS through
the server's virtual coupling (docs/python.md). Start a server with an engine-coupled session first:

    hapticd --config config/sessions/vishard3/dds-coupling.yaml &
    hapticd-python examples/python/wall_engine.py --duration 10 --push 15

--push asks the simulated operator to push along +x (N) once the device is claimed."""
import argparse
import threading

import hapticd


class Wall:
    """The proxy is the handle, held back at the wall: the coupling spring pushes the hand out of it."""

    def __init__(self, x):
        self.x = x
        self.deepest = 0.0

    def __call__(self, state):
        proxy = state.pose
        depth = proxy.position[0] - self.x
        if depth > 0.0:
            self.deepest = max(self.deepest, depth)
            proxy.position = [self.x, proxy.position[1], proxy.position[2]]
        return hapticd.EngineCommand.coupling(proxy)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--domain", type=int, default=0)
    parser.add_argument("--device", default="vishard3")
    parser.add_argument("--duration", type=float, default=10.0, help="seconds")
    parser.add_argument("--push", type=float, default=0.0, help="the simulated operator's push along +x, N")
    parser.add_argument("--id", default="py-wall-engine", help="client id (the claim's owner name)")
    args = parser.parse_args()

    with hapticd.Client(args.id, domain=args.domain) as client:
        start = client.wait_for_state(args.device, timeout=20.0).pose.position
        wall = Wall(start[0] + 0.02)
        if args.push:
            push = threading.Timer(0.2, client.operator, (args.device, "push", [args.push, 0.0, 0.0, 0.2]))
            push.start()
        stats = hapticd.run_engine(client, args.device, wall, duration=args.duration)
        print(f"answered {stats.answered} states ({stats.skipped} skipped, ended by {stats.ended_by}); "
              f"deepest {1e3 * wall.deepest:.1f} mm into the wall")


if __name__ == "__main__":
    main()
