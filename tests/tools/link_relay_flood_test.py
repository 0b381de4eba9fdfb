"""Hardening round 4, item 10: hapticd-link-relay under a flood (before: it queued delayed datagrams without bound,
63 -> 953 MB in 8 s at a 5 s delay). A sender floods the relay on loopback for 4 s at a 5 s delay; the relay's
resident memory stays under 100 MB and it counts the datagrams its full queue dropped.

    python3 link_relay_flood_test.py BIN_DIR
"""
import os
import socket
import subprocess
import sys
import time


def rss_mb(pid):
    with open(f"/proc/{pid}/status") as f:
        for line in f:
            if line.startswith("VmRSS:"):
                return int(line.split()[1]) / 1024.0
    return 0.0


def main(bin_dir):
    probe = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
    probe.bind(("127.0.0.1", 0))
    port = probe.getsockname()[1]
    probe.close()
    relay = subprocess.Popen([sys.executable, os.path.join(bin_dir, "hapticd-link-relay"), "--route",
                              f"127.0.0.1=127.0.0.2", "--ports", str(port), "--delay-ms", "5000", "--duration", "20"],
                             stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    try:
        time.sleep(1.0)
        assert relay.poll() is None, relay.stdout.read()
        flood = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
        payload = b"x" * 1400
        sent, peak = 0, 0.0
        end = time.monotonic() + 4.0
        next_look = time.monotonic()
        while time.monotonic() < end:
            for _ in range(200):
                try:
                    flood.sendto(payload, ("127.0.0.1", port))
                    sent += 1
                except OSError:
                    pass
            if time.monotonic() >= next_look:
                peak = max(peak, rss_mb(relay.pid))
                next_look += 0.25
        peak = max(peak, rss_mb(relay.pid))
        print(f"sent {sent} datagrams ({sent * 1400 / 2**20:.0f} MiB) in 4 s; the relay's peak resident memory "
              f"{peak:.1f} MB")
        relay.terminate()
        out, _ = relay.communicate(timeout=10)
        print(out.strip())
        assert peak < 100.0, f"the relay's memory grew to {peak:.0f} MB"
        overflow = int(out.rsplit("overflow ", 1)[1].split(";")[0])
        assert overflow > 0, "no datagram counted as overflow: the flood did not fill the queue"
        print("1 passed, 0 failed")
        return 0
    finally:
        if relay.poll() is None:
            relay.kill()


if __name__ == "__main__":
    sys.exit(main(sys.argv[1]))
