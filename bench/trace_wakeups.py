#!/usr/bin/env python3
"""Where a periodic real-time thread's wake-up time goes, from the kernel's own trace (ftrace, as root).

Runs hapticd's 1-DOF test session and cyclictest at the same period, SCHED_FIFO priority and locked memory, one
after the other, each under ftrace (trace clock 'mono', the clock both sleep on), and splits every wake-up of
the measuring thread (hapticd's 'hapticd-loop', cyclictest's timer thread) into:

  timer    the timer's interrupt handler runs late: from the deadline (the hrtimer's expiry) to the handler
           (hrtimer_expire_entry's 'now') - the hardware timer, the hypervisor's injection, interrupts off;
  wake     from the handler to the thread back in user space (clock_nanosleep's raw_syscalls:sys_exit): the
           scheduler switching from what ran on the CPU (a task in the kernel that does not yield at once, on
           a kernel without full preemption), or the CPU leaving idle.

(The switch into the thread is not always traced: from a polling idle CPU this kernel leaves sched_switch out,
so the split is at the handler, whose trace line names the task that was on the CPU.) Prints per program the
percentiles of each part and of the total, what was on the CPU at the slowest wake-ups, the CPU's time by task
during the run, and the events on the CPU before the slowest wake-ups.

With --probe KB[:THREADS] ... it also traces bench/wake_probe (built with the benchmarks): cyclictest's loop
with KB of memory written after every wake-up and THREADS other sleeping threads in the process - what the
server's loop has and cyclictest's has not - one run per value, to tell which of them slows the wake part.

Usage: sudo python3 bench/trace_wakeups.py [--rate 2000] [--seconds 10] [--cpu N] [--build build/default]
       [--out DIR] [--top 5] [--probe 0 64 1024:8] [--no-hapticd]
"""
import argparse
import collections
import os
import re
import shutil
import subprocess
import sys
import tempfile

TRACEFS = "/sys/kernel/tracing"
EVENTS = ["sched/sched_switch", "sched/sched_wakeup", "timer/hrtimer_start", "timer/hrtimer_expire_entry",
          "raw_syscalls/sys_exit", "irq/irq_handler_entry", "irq/softirq_entry", "irq_vectors/local_timer_entry",
          "irq_vectors/call_function_single_entry", "irq_vectors/reschedule_entry"]
LINE = re.compile(r"^\s*(?P<comm>.{1,16}?)-(?P<pid>\d+)\s+\[(?P<cpu>\d+)\]\s+\S+\s+(?P<ts>\d+\.\d+): "
                  r"(?P<event>\w+): (?P<fields>.*)$")


def write(name, text):
    with open(os.path.join(TRACEFS, name), "w") as f:
        f.write(text)


def set_up_tracing(buffer_kb):
    if not os.path.exists(os.path.join(TRACEFS, "trace")):
        subprocess.run(["mount", "-t", "tracefs", "nodev", TRACEFS], check=True)
    write("tracing_on", "0")
    write("current_tracer", "nop")
    write("trace_clock", "mono")
    write("buffer_size_kb", str(buffer_kb))
    write("events/enable", "0")
    for e in EVENTS:
        path = os.path.join(TRACEFS, "events", e, "enable")
        if os.path.exists(path):
            write(os.path.join("events", e, "enable"), "1")
    write("trace", "")


def traced(command, trace_file):
    """Runs command with tracing on; saves the trace text. Returns the command's exit code."""
    write("trace", "")
    write("tracing_on", "1")
    rc = subprocess.run(command, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL).returncode
    write("tracing_on", "0")
    with open(os.path.join(TRACEFS, "trace")) as src, open(trace_file, "w") as dst:
        shutil.copyfileobj(src, dst)
    return rc


def fields_of(text):
    out = {}
    for m in re.finditer(r"(\w+)=(\S+)", text):
        out[m.group(1)] = m.group(2)
    return out


def parse(trace_file):
    with open(trace_file) as f:
        for line in f:
            m = LINE.match(line)
            if m:
                yield (m.group("comm").strip(), int(m.group("pid")), int(m.group("cpu")),
                       round(float(m.group("ts")) * 1e9), m.group("event"), m.group("fields"))


def measuring_thread(trace_file, comm):
    """The thread named comm that hrtimer_wakeup wakes most often (cyclictest's main thread shares its name)."""
    woken = collections.Counter()
    for c, pid, _, _, event, fields in parse(trace_file):
        if event == "sched_wakeup":
            f = fields_of(fields)
            if f.get("comm") == comm:
                woken[int(f["pid"])] += 1
    return woken.most_common(1)[0][0] if woken else None


def analyse(trace_file, tid, top):
    """Splits each wake-up of tid into timer / wake; returns the rows, the slow cases' contexts, the thread's
    CPU and the CPU time of every task on it."""
    expires = {}           # hrtimer address -> expiry (ns) for tid's sleeps
    wake = None            # the current wake-up being followed
    rows = []
    recent = collections.defaultdict(lambda: collections.deque(maxlen=12))  # per CPU: the last events
    cpu_time = collections.Counter()  # (cpu, task) -> ns on that CPU, from sched_switch
    running = {}           # cpu -> (task, since)
    loop_cpu = collections.Counter()
    contexts = []
    for comm, pid, cpu, ts, event, fields in parse(trace_file):
        recent[cpu].append((ts, comm, event, fields[:90]))
        if event == "sched_switch":
            f = fields_of(fields)
            prev = running.get(cpu)
            if prev is not None:
                cpu_time[(cpu, prev[0])] += ts - prev[1]
            running[cpu] = (f.get("next_comm", "?") + ":" + f.get("next_pid", "?"), ts)
        if pid == tid and event == "hrtimer_start":
            f = fields_of(fields)
            if f.get("function") == "hrtimer_wakeup":
                expires[f["hrtimer"]] = int(f["expires"])
        elif event == "hrtimer_expire_entry":
            f = fields_of(fields)
            if f.get("hrtimer") in expires and f.get("function") == "hrtimer_wakeup":
                wake = {"deadline": expires.pop(f["hrtimer"]), "handler": int(f["now"]), "cpu": cpu,
                        "on_cpu": comm}
        elif event == "sys_exit" and pid == tid and wake is not None:
            total = ts - wake["deadline"]
            rows.append((total, wake["handler"] - wake["deadline"], ts - wake["handler"], wake["on_cpu"]))
            loop_cpu[cpu] += 1
            if top > 0 and (len(contexts) < top or total > contexts[-1][0]):
                contexts.append((total, wake["deadline"], list(recent[cpu])))
                contexts.sort(key=lambda c: -c[0])
                del contexts[top:]
            wake = None
    home = loop_cpu.most_common(1)[0][0] if loop_cpu else 0
    on_home = collections.Counter({k[1]: v for k, v in cpu_time.items() if k[0] == home})
    return rows, contexts, home, on_home


def percentile(values, p):
    s = sorted(values)
    return s[min(len(s) - 1, int(p * len(s)))] if s else float("nan")


def report(name, rows, contexts, home, on_home, top):
    print(f"\n### {name}: {len(rows)} wake-ups traced (the thread mostly on CPU {home})\n")
    print("| part | p50 [us] | p99 [us] | p99.9 [us] | max [us] |")
    print("|---|---|---|---|---|")
    for i, part in enumerate(["total", "timer", "wake"]):
        v = [r[i] / 1000 for r in rows]
        print(f"| {part} | {percentile(v, 0.5):.1f} | {percentile(v, 0.99):.1f} | {percentile(v, 0.999):.1f} | "
              f"{max(v) if v else float('nan'):.1f} |")
    slow = sorted(rows, key=lambda r: -r[0])[:max(1, len(rows) // 100)]
    if slow:
        whole = sum(r[0] for r in slow)
        print(f"\nThe slowest 1 % ({len(slow)} wake-ups, from {slow[-1][0] / 1000:.1f} us): timer "
              f"{sum(r[1] for r in slow) / whole:.0%}, wake {sum(r[2] for r in slow) / whole:.0%} of their time; "
              "on the CPU when the timer fired: " +
              ", ".join(f"{c} {n}" for c, n in collections.Counter(r[3] for r in slow).most_common(6)))
    busy = sum(on_home.values())
    print(f"\nCPU {home}'s time by task during the run (top 8 of {busy / 1e9:.2f} s): " +
          ", ".join(f"{c} {t / 1e6:.0f} ms" for c, t in on_home.most_common(8)))
    for total, deadline, events in contexts[:top]:
        print(f"\n{total / 1000:.1f} us late (deadline {deadline / 1e9:.6f}); the last events on its CPU:")
        for ts, comm, event, fields in events:
            print(f"    {(ts - deadline) / 1000:+9.1f} us  {comm:16.16} {event:24.24} {fields}")


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--rate", type=int, default=2000)
    ap.add_argument("--seconds", type=float, default=10)
    ap.add_argument("--build", default="build/default")
    ap.add_argument("--out", default=None)
    ap.add_argument("--top", type=int, default=5, help="slowest wake-ups shown with their context")
    ap.add_argument("--priority", type=int, default=80)
    ap.add_argument("--cpu", type=int, default=-1, help="pin both measuring threads to this CPU (-1: not pinned)")
    ap.add_argument("--probe", nargs="*", default=[], metavar="KB[:THREADS]",
                    help="also trace bench/wake_probe touching KB after each wake-up, with THREADS other threads")
    ap.add_argument("--no-hapticd", action="store_true", help="leave the server out (cyclictest and probes only)")
    args = ap.parse_args()
    if os.geteuid() != 0:
        sys.exit("trace_wakeups.py: ftrace needs root")
    root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    out = args.out or tempfile.mkdtemp(prefix="trace_wakeups.")
    os.makedirs(out, exist_ok=True)
    period_us = 1000000 // args.rate
    with open(os.path.join(root, "config/sessions/test-mass-spring.yaml")) as f:
        session = f.read()
    session = session.replace("rate_hz: 2000", f"rate_hz: {args.rate}").replace(
        "realtime_priority: 80", f"realtime_priority: {args.priority}\n  cpu_dma_latency_us: 0\n  cpu: {args.cpu}").replace(
        "server:", f"server:\n  plugin_paths: [{os.path.join(root, args.build, 'lib/hapticd/plugins')}]", 1)
    session_file = os.path.join(out, "session.yaml")
    with open(session_file, "w") as f:
        f.write(session)
    set_up_tracing(buffer_kb=int(args.seconds * args.rate * 2 // 10) + 20000)
    runs = [("hapticd", "hapticd-loop",
             [os.path.join(root, args.build, "bin/hapticd"), "--config", session_file, "--duration",
              str(args.seconds), "--log-level", "warn"]),
            ("cyclictest", "cyclictest",
             ["cyclictest", "-q", "-p", str(args.priority), "-i", str(period_us), "-l",
              str(int(args.seconds * args.rate)), "-m"] + (["-a", str(args.cpu)] if args.cpu >= 0 else []))]
    if args.no_hapticd:
        runs = runs[1:]
    for probe in args.probe:
        kb, _, threads = probe.partition(":")
        runs.append((f"wake_probe {kb} KB, {threads or 0} threads", "wake-probe",
                     [os.path.join(root, args.build, "bin/wake_probe"), "--rate", str(args.rate), "--seconds",
                      str(args.seconds), "--priority", str(args.priority), "--cpu", str(args.cpu), "--touch-kb", kb,
                      "--threads", threads or "0"]))
    print(f"{args.rate} Hz, {args.seconds} s each, SCHED_FIFO {args.priority}, mlockall, CPU latency limit 0, "
          f"{'CPU ' + str(args.cpu) if args.cpu >= 0 else 'not pinned'}; "
          f"trace files in {out}")
    for name, comm, command in runs:
        trace_file = os.path.join(out, f"{name}.trace")
        rc = traced(command, trace_file)
        tid = measuring_thread(trace_file, comm)
        if tid is None:
            print(f"\n### {name}: no wake-ups of '{comm}' in the trace (exit {rc})")
            continue
        report(name + ("" if rc == 0 else f" (exit {rc})"), *analyse(trace_file, tid, args.top), args.top)
    write("events/enable", "0")
    write("buffer_size_kb", "1408")


if __name__ == "__main__":
    main()
