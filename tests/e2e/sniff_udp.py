#!/usr/bin/python3
"""Captures the UDP payloads sent on the loopback interface to a range of ports for a while (an AF_PACKET socket:
root) and says whether any of them contains one of the given texts. For the DDS Security test: the payloads of
a domain's traffic must not show the device's name or its joint names in plain text.
Usage: sniff_udp.py SECONDS PORT_MIN PORT_MAX TEXT...   prints "packets N bytes B found TEXT,..." """
import socket
import struct
import sys
import time

seconds, port_min, port_max = float(sys.argv[1]), int(sys.argv[2]), int(sys.argv[3])
texts = [t.encode() for t in sys.argv[4:]]
s = socket.socket(socket.AF_PACKET, socket.SOCK_RAW, socket.ntohs(0x0003))
s.bind(("lo", 0))
s.settimeout(0.2)
found, packets, total = set(), 0, 0
end = time.monotonic() + seconds
while time.monotonic() < end:
    try:
        frame = s.recv(65535)
    except socket.timeout:
        continue
    if len(frame) < 42 or frame[12:14] != b"\x08\x00":  # IPv4 over the loopback's Ethernet header
        continue
    ihl = (frame[14] & 0x0F) * 4
    if frame[23] != 17:  # UDP
        continue
    udp = 14 + ihl
    dport = struct.unpack("!H", frame[udp + 2:udp + 4])[0]
    if not port_min <= dport <= port_max:
        continue
    payload = frame[udp + 8:]
    packets += 1
    total += len(payload)
    for t in texts:
        if t in payload:
            found.add(t.decode())
print(f"packets {packets} bytes {total} found {','.join(sorted(found)) or '-'}")
