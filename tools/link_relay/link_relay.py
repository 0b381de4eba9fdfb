#!/usr/bin/env python3
"""hapticd-link-relay: a network in the middle, in user space, for machines or namespaces without netem.

Relays UDP datagrams between two sides - each datagram arriving at LISTEN_ADDRESS:PORT goes to TARGET_ADDRESS:PORT
(the same port) - after a delay, with jitter and random loss drawn from a seeded generator. Two servers of a
teleoperation pair that can reach each other only through it (docs/teleoperation.md, "The channel") then talk
DDS (RTPS over UDP) across a delayed, lossy link. Each side's Cyclone DDS advertises the relay's address facing
the other side (ExternalNetworkAddress) and names it as its peer, so that everything goes through the relay.

  hapticd-link-relay --route 192.0.2.2=192.0.2.130 --route 192.0.2.129=192.0.2.1 \\
      --ports 7410-7419 --delay-ms 50 --jitter-ms 5 --loss 0.05 --seed 1 --duration 60

Ports: Cyclone's unicast discovery and data ports of domain D are 7400 + 250 D + 10 + 2 i and + 11 + 2 i for
participant index i. The datagrams in flight are bounded (--max-queued-mb, as a router's queue is): one that
arrives while the queue is full is dropped and counted as an overflow, so a flood costs bounded memory. Prints
what it relayed, dropped and dropped for overflow per direction at the end (SIGINT, SIGTERM or --duration), and how
long it held the datagrams it sent on average (from reading one to sending it: the delay and jitter asked, plus the
relay's own lateness - its wait's millisecond granularity, its scheduling).
Standard library only.
"""
import argparse
import heapq
import random
import selectors
import signal
import socket
import sys
import time


def parse_ports(text):
    ports = set()
    for part in text.split(","):
        if "-" in part:
            lo, hi = part.split("-", 1)
            ports.update(range(int(lo), int(hi) + 1))
        else:
            ports.add(int(part))
    if not ports or min(ports) < 1 or max(ports) > 65535 or len(ports) > 512:
        raise argparse.ArgumentTypeError("1 to 512 ports in 1..65535, e.g. 7410-7419")
    return sorted(ports)


def parse_route(text):
    if "=" not in text:
        raise argparse.ArgumentTypeError("LISTEN_ADDRESS=TARGET_ADDRESS, got " + repr(text))
    listen, target = text.split("=", 1)
    for a in (listen, target):
        socket.inet_aton(a)  # raises OSError (argparse reports it) for a malformed address
    return listen, target


def main(argv=None):
    p = argparse.ArgumentParser(prog="hapticd-link-relay",
                                description="a delaying, lossy UDP relay between two sides (docs/teleoperation.md)")
    p.add_argument("--route", type=parse_route, action="append", required=True,
                   help="LISTEN_ADDRESS=TARGET_ADDRESS: what arrives at the first goes to the second (repeatable)")
    p.add_argument("--ports", type=parse_ports, required=True, help="UDP ports relayed, e.g. 7410-7419,7660-7669")
    p.add_argument("--delay-ms", type=float, default=0.0, help="one-way delay added to every datagram")
    p.add_argument("--jitter-ms", type=float, default=0.0, help="each datagram's extra delay, uniform up to this")
    p.add_argument("--loss", type=float, default=0.0, help="probability that a datagram is dropped, 0..0.999")
    p.add_argument("--seed", type=int, default=1, help="the generator's seed (the same seed drops the same datagrams)")
    p.add_argument("--duration", type=float, default=0.0, help="seconds to run (0: until stopped)")
    p.add_argument("--max-queued-mb", type=float, default=16.0,
                   help="the datagrams in flight at most (MiB); more are dropped and counted as overflow")
    a = p.parse_args(argv)
    if not (0.0 <= a.loss <= 0.999) or a.delay_ms < 0 or a.jitter_ms < 0 or a.delay_ms > 10000 or a.jitter_ms > 10000:
        p.error("--loss in 0..0.999, --delay-ms and --jitter-ms in 0..10000")
    if not (0.0625 <= a.max_queued_mb <= 1024):
        p.error("--max-queued-mb in 0.0625..1024")
    max_queued = int(a.max_queued_mb * (1 << 20))

    rng = random.Random(a.seed)
    sel = selectors.DefaultSelector()
    senders = {}  # target address -> a socket to send from
    counts = {}  # route -> [relayed, dropped, overflow, sent, held seconds in total]
    for listen, target in a.route:
        counts[(listen, target)] = [0, 0, 0, 0, 0.0]
        if target not in senders:
            s = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
            s.setsockopt(socket.SOL_SOCKET, socket.SO_SNDBUF, 4 << 20)
            senders[target] = s
        for port in a.ports:
            s = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
            s.setsockopt(socket.SOL_SOCKET, socket.SO_RCVBUF, 4 << 20)
            try:
                s.bind((listen, port))
            except OSError as e:
                print(f"hapticd-link-relay: cannot listen on {listen}:{port}: {e}", file=sys.stderr)
                return 2
            s.setblocking(False)
            sel.register(s, selectors.EVENT_READ, (listen, target, port))

    stop = [False]
    for sig in (signal.SIGINT, signal.SIGTERM):
        signal.signal(sig, lambda *_: stop.__setitem__(0, True))
    pending = []  # (due, order, target, port, data)
    queued = 0  # bytes in pending
    order = 0
    end = time.monotonic() + a.duration if a.duration > 0 else float("inf")
    print(f"hapticd-link-relay: {len(a.route)} route(s), {len(a.ports)} port(s) each; delay {a.delay_ms:g} ms, "
          f"jitter {a.jitter_ms:g} ms, loss {a.loss:g}, seed {a.seed}", flush=True)
    while not stop[0] and time.monotonic() < end:
        now = time.monotonic()
        timeout = max(0.0, min(pending[0][0] - now, 0.05)) if pending else 0.05
        for key, _ in sel.select(timeout):
            listen, target, port = key.data
            while True:
                try:
                    data = key.fileobj.recv(65536)
                except BlockingIOError:
                    break
                # Held from when it was read (a time taken before the select's wait would release it early by
                # that wait; a late reading only delays it). Both draws for every datagram: a setting changes only
                # what it governs.
                arrived = time.monotonic()
                lost = rng.random() < a.loss
                jitter = rng.random() * a.jitter_ms
                if lost:
                    counts[(listen, target)][1] += 1
                    continue
                if queued + len(data) > max_queued:
                    counts[(listen, target)][2] += 1
                    continue
                order += 1
                heapq.heappush(pending, (arrived + (a.delay_ms + jitter) * 1e-3, order, listen, target, port, data, arrived))
                queued += len(data)
                counts[(listen, target)][0] += 1
        now = time.monotonic()
        while pending and pending[0][0] <= now:
            _, _, listen, target, port, data, arrived = heapq.heappop(pending)
            queued -= len(data)
            try:
                senders[target].sendto(data, (target, port))
            except OSError:
                continue  # nobody there (yet): as a network would lose it
            route = counts[(listen, target)]
            route[3] += 1
            route[4] += time.monotonic() - arrived  # what it was held, as measured (the delay the sides should read)
    for (listen, target), (relayed, dropped, overflow, sent, held) in counts.items():
        print(f"hapticd-link-relay: {listen} -> {target}: relayed {relayed}, dropped {dropped}, "
              f"overflow {overflow}; held {1e3 * held / max(sent, 1):.2f} ms on average", flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
