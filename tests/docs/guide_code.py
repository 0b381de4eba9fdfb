#!/usr/bin/env python3
"""Writes the code blocks of the engine guides that say they are compiled (a `<!-- compiled: PATH -->` line right
before a fenced block) into OUT_DIR/PATH, so that a test compiles the guides' code as written
(docs/unreal.md, docs/godot.md; tests/e2e/out_of_tree_plugin_test.sh compiles them against the installed package).

Usage: guide_code.py OUT_DIR DOC...
"""
import pathlib
import re
import sys


def main():
    out = pathlib.Path(sys.argv[1])
    written = 0
    for doc in sys.argv[2:]:
        lines = pathlib.Path(doc).read_text().splitlines()
        for i, line in enumerate(lines):
            m = re.match(r"^<!-- compiled: (\S+) -->$", line.strip())
            if not m:
                continue
            if i + 1 >= len(lines) or not lines[i + 1].startswith("```"):
                sys.exit(f"{doc}:{i + 1}: '{line.strip()}' is not followed by a code block")
            end = next((k for k in range(i + 2, len(lines)) if lines[k].startswith("```")), None)
            if end is None:
                sys.exit(f"{doc}:{i + 2}: the code block does not end")
            target = out / m.group(1)
            target.parent.mkdir(parents=True, exist_ok=True)
            target.write_text("\n".join(lines[i + 2:end]) + "\n")
            written += 1
    if written == 0:
        sys.exit("no compiled code blocks found")
    print(f"{written} code blocks written")


if __name__ == "__main__":
    main()
