"""The round-trip figures of one server run, from its `hapticd --stats-json` report: state written -> command
accepted (p50, p99, how many) and the share of commands the loop applied in the cycle after their state's. Shared by
the engine benchmarks (python_engine_round_trip.py, engine_languages_round_trip.py)."""
import json


def round_trip_of(stats_path):
    with open(stats_path) as f:
        report = json.load(f)
    rt = report["dds_round_trip_us"]
    applied = report["dds_applied_after_cycles"]
    return {"p50": rt["p50"], "p99": rt["p99"], "count": rt["count"],
            "next_cycle": 100.0 * applied[1] / max(1, sum(applied)), "overruns": report["overruns"]}
