#!/usr/bin/env python3
"""The wire types' one description (idl/hapticd_wire.toml, docs/wire-types.md):
- the committed idl/hapticd_msg.idl is what the generator makes of the table (a reader of the source tree and a
  Fast DDS user see the data model the build compiles);
- a field added to the table reaches every form: the IDL, the C header, the C# struct, the Python stub and class,
  the copies DDS -> C++ -> C, and the engine socket's JSON when it names a key;
- a bad table is refused with the table's path and the field's name, and nothing is written.
Usage: wire_types_test.py SOURCE_DIR GENERATED_DIR"""
import subprocess
import sys
import tempfile
from pathlib import Path

source, generated = Path(sys.argv[1]), Path(sys.argv[2])
idl_dir = source / "idl"
failures = 0


def check(ok: bool, what: str) -> None:
    global failures
    print(("ok: " if ok else "FAIL: ") + what)
    failures += 0 if ok else 1


def generate(table: Path, out: Path) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, str(idl_dir / "generate_wire.py"), str(table),
                           str(idl_dir / "hapticd_msg.idl.in"), str(source / "python/hapticd/_hapticd.pyi.in"),
                           str(out)], capture_output=True, text=True, timeout=60)


committed = (idl_dir / "hapticd_msg.idl").read_text()
check(committed == (generated / "idl/hapticd_msg.idl").read_text(),
      "idl/hapticd_msg.idl is the generated one (else: cp build/<preset>/generated/wire/idl/hapticd_msg.idl idl/)")

table_text = (idl_dir / "hapticd_wire.toml").read_text()
anchor = '  ["engine_serial", "u64",'
assert anchor in table_text, "the table's DeviceState has no engine_serial line to add after"
with tempfile.TemporaryDirectory() as tmp:
    tmp = Path(tmp)
    added = table_text.replace(anchor, '  ["probe_force_n", "f64", "a test field", { json = "state:probe_force" }],\n'
                               + anchor, 1)
    (tmp / "added.toml").write_text(added)
    run = generate(tmp / "added.toml", tmp / "added")
    check(run.returncode == 0, f"the table with one field more generates ({run.stderr.strip()})")
    forms = {
        "idl/hapticd_msg.idl": "double probe_force_n;",
        "include/hapticd/client_types.h": "double probe_force_n;",
        "csharp/NativeTypes.g.cs": "public double probe_force_n;",
        "python/_hapticd.pyi": "probe_force_n: float",
        "cpp/hapticd_wire/from_msg.inc": "get(in.probe_force_n, out.probe_force_n);",
        "cpp/hapticd_wire/to_c.inc": "put(in.probe_force_n, out.probe_force_n);",
        "cpp/hapticd_wire/python_fields.inc": 'c.def_readonly("probe_force_n", &DeviceState::probe_force_n',
        "cpp/hapticd_wire/socket_json.inc": 'json_member(out, first, "probe_force");',
    }
    for name, text in forms.items():
        body = (tmp / "added" / name).read_text() if (tmp / "added" / name).exists() else ""
        check(text in body, f"the added field is in {name}")
    # In the IDL and C struct of DeviceState, just before engine_serial (the table's order is the layout's).
    idl = (tmp / "added/idl/hapticd_msg.idl").read_text()
    check(idl.index("double probe_force_n;") < idl.index("unsigned long long engine_serial;") and
          idl.index("struct DeviceState {") < idl.index("double probe_force_n;"),
          "the IDL has it in DeviceState, in the table's order")

    bad = table_text.replace('  ["gripper", "f64",', '  ["gripper", "f63",', 1)
    (tmp / "bad.toml").write_text(bad)
    run = generate(tmp / "bad.toml", tmp / "bad")
    check(run.returncode == 1 and "bad.toml" in run.stderr and "DeviceState.gripper" in run.stderr and
          "f63" in run.stderr, f"a bad type is refused naming the table and the field: {run.stderr.strip()}")
    check(not (tmp / "bad").exists(), "nothing is written for a bad table")
    unknown = table_text.replace('{ bound = "MAX_JOINTS" }],\n  ["position", "joints"',
                                 '{ bound = "MAX_JOINTS", colour = 1 }],\n  ["position", "joints"', 1)
    (tmp / "unknown.toml").write_text(unknown)
    run = generate(tmp / "unknown.toml", tmp / "unknown")
    check(run.returncode == 1 and "DeviceState.dof" in run.stderr and "colour" in run.stderr,
          f"an unknown option is refused: {run.stderr.strip()}")
    (tmp / "broken.toml").write_text(table_text + "\n[struct.X\n")
    run = generate(tmp / "broken.toml", tmp / "broken")
    check(run.returncode == 1 and "broken.toml" in run.stderr and "line" in run.stderr,
          f"a TOML syntax error names the table and the line: {run.stderr.strip()}")

sys.exit(1 if failures else 0)
