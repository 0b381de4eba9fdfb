#!/usr/bin/env python3
"""The README's and docs' example commands parse with the programs' real command lines.

Every line of a ```sh block in README.md and docs/*.md that calls one of the project's programs is run with
HAPTICD_PARSE_ONLY=1 (the program parses its command line - subcommands, options, value checks - then exits
without doing anything) from the source root; a hapticd command with --config also checks that session file
for real, with the command's --set overrides (hapticd --check-config: it loads and configures its plugins) -
unless an override names a recording (.h5) that an earlier command of the docs would have made. Synopsis lines (placeholders in capitals,
[optional] parts, a|b alternatives, ...) say what may be written, not a command: they are counted and skipped.

Usage: docs_commands_test.py SOURCE_DIR BIN_DIR
"""
import os
import pathlib
import re
import shlex
import subprocess
import sys

PROGRAMS = ("hapticd", "hapticctl", "hapticd-eval", "hapticd-scene-engine", "hapticd-admittance-engine",
            "hapticd-bimanual-engine")
MIN_CHECKED = 20  # fewer: the extraction broke, not the docs


def command_lines(path):
    """(line number, command) of every line in a ```sh block, continuations joined, comments dropped."""
    lines = path.read_text().splitlines()
    in_sh = in_block = False
    i = 0
    while i < len(lines):
        line, number = lines[i], i + 1
        fence = re.match(r"^\s*```(\w*)", line)
        if fence:
            in_sh = not in_block and fence.group(1) in ("sh", "bash", "console")
            in_block = not in_block
        elif in_sh:
            while line.rstrip().endswith("\\") and i + 1 < len(lines):
                i += 1
                line = line.rstrip()[:-1] + " " + lines[i].strip()
            text = re.sub(r"\s+#\s.*$", "", line).strip().rstrip("&").strip()
            if text:
                yield number, text
        i += 1


def is_synopsis(args):
    return any(re.search(r"[\[\]|]|\.\.\.", a) or re.fullmatch(r"[A-Z][A-Z0-9_.=]*(\.[a-z0-9]+)?", a)
               for a in args[1:])


def main():
    source, bin_dir = pathlib.Path(sys.argv[1]), pathlib.Path(sys.argv[2])
    files = [source / "README.md"] + sorted((source / "docs").glob("*.md"))
    checked, synopses, failures = 0, 0, []
    for path in files:
        for number, text in command_lines(path):
            try:
                words = shlex.split(text)
            except ValueError as e:
                failures.append(f"{path.name}:{number}: {text}: not a shell command ({e})")
                continue
            env_vars = {}
            while words and re.fullmatch(r"[A-Z_][A-Z0-9_]*=\S*", words[0]):
                key, value = words.pop(0).split("=", 1)
                env_vars[key] = value
            if not words or words[0] not in PROGRAMS:
                continue
            if is_synopsis(words):
                synopses += 1
                continue
            where = f"{path.relative_to(source)}:{number}"
            env = dict(os.environ, HAPTICD_PARSE_ONLY="1", **env_vars)
            run = subprocess.run([str(bin_dir / words[0])] + words[1:], cwd=source, env=env, capture_output=True,
                                 text=True, timeout=30)
            if run.returncode != 0 or "the command line parsed" not in run.stderr + run.stdout:
                failures.append(f"{where}: {text}\n    exit {run.returncode}: {(run.stderr or run.stdout).strip()}")
                continue
            # The session file checks, with the command's overrides - unless one names a recording an earlier
            # command of the docs makes (the playback device's): then the command only parses.
            overrides = [w for k, w in enumerate(words) if k > 0 and words[k - 1] == "--set"]
            if words[0] == "hapticd" and "--config" in words and not any(o.endswith(".h5") for o in overrides):
                config = words[words.index("--config") + 1]
                sets = [a for o in overrides for a in ("--set", o)]
                check = subprocess.run([str(bin_dir / "hapticd"), "--check-config", config, *sets, "--log-level",
                                        "warn"], cwd=source, capture_output=True, text=True, timeout=60)
                if check.returncode != 0:
                    failures.append(f"{where}: {config} does not check: {check.stderr.strip()}")
                    continue
            checked += 1
            print(f"ok {where}: {text}")
    print(f"{checked} example commands parse, {synopses} synopsis lines skipped, {len(failures)} failed")
    for f in failures:
        print("FAIL", f)
    if checked < MIN_CHECKED:
        print(f"FAIL: only {checked} commands found (at least {MIN_CHECKED} expected)")
        return 1
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
