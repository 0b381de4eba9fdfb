#!/usr/bin/env python3
"""A newcomer's path through the docs, run as written: every ```sh block marked `<!-- newcomer -->` (the line
before its fence) in docs/engines.md first - it installs hapticd to a fresh prefix - then in the other pages in
alphabetical order, each in the order it appears, in one bash shell (so a block's variables and exports reach the
next), from the source folder, with HOME an empty folder of this test's own and `build/default` (the README's build)
meaning the build tree under test (as root without sudo, `sudo CMD` runs CMD). `<!-- newcomer expect="REGEX" -->` also requires the block's output (standard
output and error) to match REGEX. A block that fails, or whose output does not match, fails the test with that
block's place and output; every block's output is kept in WORK_DIR.

Usage: newcomer_test.py SOURCE_DIR BUILD_DIR WORK_DIR
"""
import pathlib
import re
import shlex
import shutil
import subprocess
import sys

MARK = re.compile(r'^<!--\s*newcomer(?:\s+expect="([^"]*)")?\s*-->\s*$')


def blocks(path):
    """(line number, expected regex or None, text) of each marked sh block."""
    lines = path.read_text().splitlines()
    i = 0
    while i < len(lines):
        mark = MARK.match(lines[i].strip())
        if mark and i + 1 < len(lines) and re.match(r"^\s*```(sh|bash)\s*$", lines[i + 1]):
            start = i + 2
            end = start
            while end < len(lines) and not re.match(r"^\s*```\s*$", lines[end]):
                end += 1
            yield start, mark.group(1), "\n".join(lines[start:end])
            i = end
        i += 1


def main():
    source, build, work = (pathlib.Path(a).resolve() for a in sys.argv[1:4])
    shutil.rmtree(work, ignore_errors=True)
    (work / "home").mkdir(parents=True)
    pages = [source / "docs" / "engines.md"] + sorted(
        p for p in (source / "docs").glob("*.md") if p.name != "engines.md") + [source / "README.md"]
    script = ["set -euo pipefail",
              # As root on a machine without sudo (a CI container), the docs' `sudo` runs the command itself.
              'if [ "$(id -u)" -eq 0 ] && ! command -v sudo > /dev/null; then sudo() { "$@"; }; fi',
              "trap '__nc_status=$?; kill $(jobs -p) 2> /dev/null || true; wait 2> /dev/null || true; "
              "if [ $__nc_status -ne 0 ]; then echo \"FAIL: $__nc_where (exit $__nc_status)\"; cat \"$__nc_out\"; fi' EXIT",
              "fail() { echo \"FAIL: $*\"; cat \"$__nc_out\"; exit 1; }"]
    count = 0
    for page in pages:
        for line, expect, text in blocks(page):
            count += 1
            where = f"{page.relative_to(source)}:{line}"
            text = text.replace("build/default", str(build))
            out = work / f"block-{count:02d}.log"
            script += [f"__nc_where={shlex.quote(where)} __nc_out={shlex.quote(str(out))}",
                       f"echo \"--- {where}\"",
                       "{", text, "} > \"$__nc_out\" 2>&1"]
            if expect:
                # (The expectation as an argument of its own: quoted inside a double-quoted message, an apostrophe
                # in it broke the script.)
                script.append(f"grep -Eq -e {shlex.quote(expect)} \"$__nc_out\" || "
                              f"fail {shlex.quote(where + ': the output does not match')} {shlex.quote(expect)}")
            script.append("tail -n 3 \"$__nc_out\"")
    if count < 5:
        print(f"FAIL: only {count} marked blocks found (the extraction broke, not the docs)")
        return 1
    (work / "newcomer.sh").write_text("\n".join(script) + "\n")
    env = {k: v for k, v in __import__("os").environ.items()
           if k not in ("HAPTICD_DDS_NETWORK", "HAPTICD_DDS_CONFIG", "CYCLONEDDS_URI", "PKG_CONFIG_PATH",
                        "LD_LIBRARY_PATH")}
    env["HOME"] = str(work / "home")
    (work / "tmp").mkdir()
    env["TMPDIR"] = str(work / "tmp")  # what the docs' commands make with mktemp stays in WORK_DIR
    try:
        r = subprocess.run(["bash", str(work / "newcomer.sh")], cwd=source, env=env, timeout=1200)
    except subprocess.TimeoutExpired:
        print("FAIL: the newcomer's path took over 20 minutes")
        return 1
    if r.returncode == 0:
        print(f"{count} blocks of the docs ran as written from a fresh prefix")
    return r.returncode


if __name__ == "__main__":
    sys.exit(main())
