#!/usr/bin/env python3
"""The README's and docs' example commands parse with the programs' real command lines.

Every line of a ```sh block in README.md and docs/*.md that calls one of the project's programs is run with
HAPTICD_PARSE_ONLY=1 (the program parses its command line - subcommands, options, value checks - then exits
without doing anything) from the source root; a hapticd command with --config also checks that session file
for real, with the command's --set overrides (hapticd --check-config: it loads and configures its plugins) -
unless an override names a recording (.h5) that an earlier command of the docs would have made. Synopsis lines (placeholders in capitals,
[optional] parts, a|b alternatives, ...) say what may be written, not a command: they are counted and skipped.

A line whose comment says `# makes FILE` made a file the docs show (a figure's or a table's data): it is run for
real, writing into a temporary folder instead, and what it makes is compared with the committed FILE - numbers
within a relative 1e-6, text equal, paths of the machine it ran on ignored - so the docs' figures are what
their commands make today. A picture (PNG) cannot come out the same twice (it is of a session running in real
time): its command must make a PNG of the committed picture's size with something drawn in it. Such a command
may be a project script run by `node` (tests/live_view/picture.mjs), which finds the programs in BIN_DIR through
HAPTICD_BIN_DIR; node lines without "# makes" are not run.

Blocks marked `<!-- newcomer -->` are not parsed here: the newcomer test runs them for real from a fresh prefix
(tests/docs/newcomer_test.py). Every other block that starts a program (not a synopsis, not a `# makes` line) must
say why it is not run: the line before its fence `<!-- not run here: REASON -->` (it needs a second machine, runs
until Ctrl-C, takes minutes, ...), so a command a reader copies is either run as written or known not to be.

Usage: docs_commands_test.py SOURCE_DIR BIN_DIR
"""
import json
import os
import pathlib
import re
import shlex
import shutil
import struct
import subprocess
import sys
import tempfile

PROGRAMS = ("hapticd", "hapticctl", "hapticd-eval", "hapticd-scene-engine", "hapticd-admittance-engine",
            "hapticd-bimanual-engine", "hapticd-mujoco-engine")
MIN_CHECKED = 20  # fewer: the extraction broke, not the docs


def command_lines(path):
    """(line number, command, comment) of every line in a ```sh block, continuations joined."""
    lines = path.read_text().splitlines()
    in_sh = in_block = False
    i = 0
    while i < len(lines):
        line, number = lines[i], i + 1
        fence = re.match(r"^\s*```(\w*)", line)
        if fence:
            # A block marked <!-- newcomer --> runs for real in the newcomer test (tests/docs/newcomer_test.py),
            # from an installed prefix its first block makes: not here.
            newcomer = i > 0 and lines[i - 1].strip().startswith("<!-- newcomer")
            in_sh = not in_block and fence.group(1) in ("sh", "bash", "console") and not newcomer
            in_block = not in_block
        elif in_sh:
            while line.rstrip().endswith("\\") and i + 1 < len(lines):
                i += 1
                line = line.rstrip()[:-1] + " " + lines[i].strip()
            comment = re.search(r"\s+#\s(.*)$", line)
            text = re.sub(r"\s+#\s.*$", "", line).strip().rstrip("&").strip()
            if text:
                yield number, text, comment.group(1).strip() if comment else ""
        i += 1


STARTERS = PROGRAMS + ("hapticd-python", "hapticd-link-relay", "node", "python3")


def unexplained_blocks(path):
    """(line number, first command) of each sh block that starts a program, is not run by the newcomer test and
    does not say why it is not run (`<!-- not run here: REASON -->` before its fence)."""
    lines = path.read_text().splitlines()
    i = 0
    while i < len(lines):
        if re.match(r"^\s*```(sh|bash)\s*$", lines[i]):
            before = lines[i - 1].strip() if i > 0 else ""
            end = i + 1
            while end < len(lines) and not re.match(r"^\s*```\s*$", lines[end]):
                end += 1
            said = before.startswith("<!-- newcomer") or re.match(r"<!-- not run here: \S.* -->$", before)
            for raw in lines[i + 1:end]:
                if said or raw.startswith(" "):
                    break
                text = re.sub(r"\s+#\s.*$", "", raw).strip().rstrip("\\").strip()
                try:
                    words = shlex.split(text)
                except ValueError:
                    continue
                while words and re.fullmatch(r"[A-Z_][A-Z0-9_]*=\S*", words[0]):
                    words.pop(0)
                starts = words and (words[0] in STARTERS or re.match(r"^(\./)?(scripts|eval)/", words[0]))
                if starts and not is_synopsis(words) and not re.search(r"#\s+makes \S+", raw):
                    yield i + 1, text
                    break
            i = end
        i += 1


def same_data(made, committed, where=""):
    """Differences between two JSON values: numbers within a relative 1e-6; "urdf" paths are the machine's."""
    if isinstance(committed, dict) and isinstance(made, dict):
        out = []
        for key in sorted(set(committed) | set(made)):
            if key == "urdf":
                continue
            if key not in made or key not in committed:
                out.append(f"{where}.{key}: only in {'the committed file' if key in committed else 'the new one'}")
            else:
                out += same_data(made[key], committed[key], f"{where}.{key}")
        return out
    if isinstance(committed, list) and isinstance(made, list):
        if len(made) != len(committed):
            return [f"{where}: {len(made)} elements, committed {len(committed)}"]
        return [d for k, (m, c) in enumerate(zip(made, committed)) for d in same_data(m, c, f"{where}[{k}]")]
    if isinstance(committed, (int, float)) and isinstance(made, (int, float)) and not isinstance(committed, bool):
        return [] if abs(made - committed) <= 1e-6 * max(1.0, abs(committed)) else [f"{where}: {made}, committed {committed}"]
    return [] if made == committed else [f"{where}: {made!r}, committed {committed!r}"]


def png_differences(made, committed):
    """A PNG of the committed one's size whose pixels are not all alike (a page that drew nothing is one colour and
    compresses to a few kB)."""
    data, reference = made.read_bytes(), committed.read_bytes()
    if data[:8] != b"\x89PNG\r\n\x1a\n":
        return ["not a PNG"]
    size, committed_size = struct.unpack(">II", data[16:24]), struct.unpack(">II", reference[16:24])
    if size != committed_size:
        return [f"{size[0]}x{size[1]} pixels, committed {committed_size[0]}x{committed_size[1]}"]
    if len(data) < len(reference) // 2:  # the page left unconnected: 19 kB against 69
        return [f"{len(data)} bytes against the committed {len(reference)}: nothing drawn?"]
    return []


def remake(bin_dir, source, words, target, scratch):
    """Runs the command for real with `target` (a committed file) written into `scratch`; the differences."""
    made = scratch / pathlib.Path(target).name
    args = [str(made) if w == target else w for w in words]
    if str(made) not in args:
        return [f"the command does not write {target}"]
    program = [shutil.which("node") or "node"] if args[0] == "node" else [str(bin_dir / args[0])]
    run = subprocess.run(program + args[1:], cwd=source, capture_output=True, text=True, timeout=120,
                         env=dict(os.environ, HAPTICD_BIN_DIR=str(bin_dir)))
    if run.returncode != 0 or not made.exists():
        return [f"exit {run.returncode}: {(run.stderr or run.stdout).strip()[-400:]}"]
    if made.suffix == ".png":
        return png_differences(made, source / target)
    if made.suffix == ".json":
        return same_data(json.loads(made.read_text()), json.loads((source / target).read_text()))
    return [] if made.read_bytes() == (source / target).read_bytes() else ["the file differs"]


def check_remade(bin_dir, source, words, target, scratch, where, failures):
    """Remakes `target` with its command; 1 when it came out as committed, else 0 with the failure recorded."""
    differences = remake(bin_dir, source, words, target, scratch)
    if differences:
        failures.append(f"{where}: {target} is not what its command makes now:\n    " + "\n    ".join(differences[:10]))
        return 0
    print(f"ok {where}: makes {target} as committed")
    return 1


def is_synopsis(args):
    return any(re.search(r"[\[\]|]|\.\.\.", a) or re.fullmatch(r"[A-Z][A-Z0-9_.=]*(\.[a-z0-9]+)?", a)
               for a in args[1:])


def main():
    source, bin_dir = pathlib.Path(sys.argv[1]), pathlib.Path(sys.argv[2])
    files = [source / "README.md"] + sorted((source / "docs").glob("*.md"))
    checked, synopses, remade, failures = 0, 0, 0, []
    scratch = pathlib.Path(tempfile.mkdtemp(prefix="hapticd-docs-"))
    for path in files:
        for number, text, comment in command_lines(path):
            try:
                words = shlex.split(text)
            except ValueError as e:
                failures.append(f"{path.name}:{number}: {text}: not a shell command ({e})")
                continue
            env_vars = {}
            while words and re.fullmatch(r"[A-Z_][A-Z0-9_]*=\S*", words[0]):
                key, value = words.pop(0).split("=", 1)
                env_vars[key] = value
            makes = re.fullmatch(r"makes (\S+)", comment)
            if words and words[0] == "node" and makes:
                remade += check_remade(bin_dir, source, words, makes.group(1), scratch,
                                       f"{path.relative_to(source)}:{number}", failures)
                continue
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
            if makes:
                remade += check_remade(bin_dir, source, words, makes.group(1), scratch, where, failures)
    for path in files:
        for number, text in unexplained_blocks(path):
            failures.append(f"{path.relative_to(source)}:{number}: this block starts a program ({text}) but the newcomer "
                            "test does not run it and the doc does not say why (<!-- not run here: REASON --> before "
                            "its fence, or <!-- newcomer --> to run it)")
    print(f"{checked} example commands parse, {remade} made their docs' files again, {synopses} synopsis lines "
          f"skipped, {len(failures)} failed")
    for f in failures:
        print("FAIL", f)
    if checked < MIN_CHECKED:
        print(f"FAIL: only {checked} commands found (at least {MIN_CHECKED} expected)")
        return 1
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
