#!/usr/bin/env python3
"""The house has no arrow against its layers (docs/architecture.md, "Layout" and "Layers").

Inside server/src a folder includes only its own headers and those of the layers below it; two folders of one
layer do not include each other. Plugins see the SDK (api/, `hapticd/...`), their own folder and plugins/common;
never a server-internal header. Clients, the evaluation suite, tools, examples and the Python bindings see the
installed libraries' headers (`hapticd/...`) and their own folder: no server internals either.

Tests, benchmarks and fuzzers are white-box: they may include anything.

Usage: layers_test.py SOURCE_DIR
"""
import pathlib
import re
import sys

# server/src, bottom to top. A folder may include its own layer's folder and any lower layer's.
LAYERS = [
    ["executor", "loader", "safety", "net"],  # the loops (generic), the plugin loader, safety, the WebSocket transport
    ["config"],                         # the session file
    ["session"],                        # one device: its chain, schemes, safety, status
    ["group"],                          # the device groups' stage
    ["cycle"],                          # a loop's devices and groups, one cycle in phases
    ["gate"],                           # what reaches the devices from outside, whatever door: claims, commands, requests
    ["recorder", "doors", "live_view"],  # around the loop: recording, the gate's doors (DDS, socket, link), live view
    ["assembly"],                       # a session built from its configuration (also the in-process Session API)
    ["app"],                            # the hapticd program: commands, the served session, signals
]
LEVEL = {folder: level for level, folders in enumerate(LAYERS) for folder in folders}
# Headers the build generates (from idl/): included without a folder from their build directory.
GENERATED = {"hapticd_msg.h", "hapticd_msgPubSubTypes.h", "hapticd_msg.hpp", "hapticd_msg.cxx", "hapticd_msgPubSubTypes.hpp", "hapticd_msgTypeObjectSupport.hpp"}
INCLUDE = re.compile(r'^\s*#\s*include\s+"([^"]+)"', re.MULTILINE)
SOURCES = ("*.cpp", "*.hpp", "*.h", "*.c", "*.in")


def includes(path):
    return INCLUDE.findall(path.read_text(errors="replace"))


def files(root):
    for pattern in SOURCES:
        yield from (p for p in root.rglob(pattern) if p.is_file())


def main():
    source = pathlib.Path(sys.argv[1])
    server = source / "server" / "src"
    problems = []
    folders = {p.name for p in server.iterdir() if p.is_dir()}
    unknown = folders - set(LEVEL)
    if unknown:
        problems.append(f"server/src: folders without a layer: {sorted(unknown)} (add them to LAYERS and the docs)")
    checked = 0
    for path in sorted(files(server)):
        mine = path.relative_to(server).parts[0]
        for inc in includes(path):
            top = inc.split("/")[0] if "/" in inc else None
            if top is None or top not in LEVEL or top == mine:
                continue
            checked += 1
            if mine not in LEVEL:
                continue
            if LEVEL[top] > LEVEL[mine]:
                problems.append(f"{path.relative_to(source)}: includes {inc}: {top}/ is above {mine}/")
            elif LEVEL[top] == LEVEL[mine]:
                problems.append(f"{path.relative_to(source)}: includes {inc}: {top}/ and {mine}/ are one layer")
    # Outside the server: no server-internal header (their folder names as include prefixes).
    # (tests/, bench/ and fuzz/ look inside on purpose: white-box tests, benchmarks and fuzzers of the internals.)
    outside = ["plugins", "clients", "eval", "tools", "examples", "python", "recording", "teleop", "scene", "dds", "api", "idl"]
    for top_folder in outside:
        root = source / top_folder
        if not root.is_dir():
            continue
        names = {p.name for p in files(root)}
        for path in sorted(files(root)):
            for inc in includes(path):
                top = inc.split("/")[0] if "/" in inc else None
                if top in LEVEL and not (path.parent / inc).exists():
                    problems.append(f"{path.relative_to(source)}: includes the server-internal {inc}")
                # An include without a folder names a header of the file's own part of the tree (a plugin's, a
                # client's), found through an include directory: one from another part (a client including a
                # plugin's header) is an arrow the prefixes above cannot see.
                if top is None and inc not in names and inc not in GENERATED:
                    problems.append(f"{path.relative_to(source)}: includes {inc}, which is not in {top_folder}/ "
                                    "(a header of another part of the tree: include it by its installed path)")
                checked += 1
    if checked < 100:
        problems.append(f"only {checked} includes checked: the scan broke")
    for p in problems:
        print("FAIL:", p)
    print(f"{checked} includes checked, {len(problems)} against the layers")
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
