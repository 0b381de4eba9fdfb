"""ROS 2's interface definitions as the DDS IDL a ROS 2 middleware puts on the wire (docs/ros2.md, "The types").

    ros2_dds_idl.py DEFINITIONS WORK_DIR OUT.idl PKG/msg/Type ... PKG/srv/Type ...

DEFINITIONS holds ROS 2's .msg and .srv files, a folder a package (idl/ros2/: the definitions as released, their
source in idl/ros2/SOURCES.md). Debian's `rosidl translate --to idl` (rosidl-tools) makes ROS 2's IDL of them in
WORK_DIR/rosidl; this reads that with ROS 2's own IDL parser
(python3-rosidl's rosidl_parser) and writes, for the types named and every type they use, the DDS form rmw_cyclonedds
and rmw_fastrtps register (as ROS 2's rosidl_generator_dds_idl writes it): each type in a module `dds_` inside its
package's and kind's (`geometry_msgs::msg::dds_::PoseStamped_`), its name with a trailing underscore, the members
as defined. A service gives its request and its response types as rmw_cyclonedds puts them on the wire: each
prefixed by the request header it writes before the payload (the client's GUID as a 64-bit number and the request's
sequence number: rmw_cyclonedds_cpp/src/serdata.hpp, cdds_request_header_t).

Needs Debian's python3 (the one with python3-rosidl): the build runs it with /usr/bin/python3.
"""
import pathlib
import subprocess
import sys

from rosidl_parser import definition as d
from rosidl_parser.parser import parse_idl_file

# ROS 2's basic types as IDL 4 names both idlc (Cyclone) and fastddsgen (Fast DDS) read.
BASIC = {
    "boolean": "boolean", "octet": "octet", "char": "char", "wchar": "wchar", "float": "float", "double": "double",
    "long double": "long double", "int8": "int8", "uint8": "uint8", "int16": "short", "uint16": "unsigned short",
    "int32": "long", "uint32": "unsigned long", "int64": "long long", "uint64": "unsigned long long",
}
HEADER = ["unsigned long long client_guid;", "long long sequence_number;"]  # rmw_cyclonedds' request header


def dds_name(t: d.NamespacedType) -> str:
    return "::".join(list(t.namespaces) + ["dds_", t.name + "_"])


def type_text(t) -> str:
    if isinstance(t, d.BasicType):
        return BASIC[t.typename]
    if isinstance(t, d.NamespacedType):
        return dds_name(t)
    if isinstance(t, d.BoundedString):
        return f"string<{t.maximum_size}>"
    if isinstance(t, d.UnboundedString):
        return "string"
    if isinstance(t, d.BoundedSequence):
        return f"sequence<{type_text(t.value_type)}, {t.maximum_size}>"
    if isinstance(t, d.UnboundedSequence):
        return f"sequence<{type_text(t.value_type)}>"
    raise SystemExit(f"ros2_dds_idl: a member of type {t!r} is not supported")


def member_text(m: d.Member) -> str:
    if isinstance(m.type, d.Array):
        return f"{type_text(m.type.value_type)} {m.name}[{m.type.size}];"
    return f"{type_text(m.type)} {m.name};"


def structures(rosidl_dir: pathlib.Path, name: str):
    """The structures of PKG/msg/Type (one) or PKG/srv/Type (request and response), from its translated IDL."""
    idl = parse_idl_file(d.IdlLocator(rosidl_dir, pathlib.Path(name + ".idl")))
    found = []
    for element in idl.content.elements:
        messages = [element] if isinstance(element, d.Message) else \
            [element.request_message, element.response_message] if isinstance(element, d.Service) else []
        for message in messages:
            if message.constants:
                raise SystemExit(f"ros2_dds_idl: {name}: constants are not supported")
            found.append((message.structure, isinstance(element, d.Service)))
    if not found:
        raise SystemExit(f"ros2_dds_idl: {name}: no message or service in {name}.idl")
    return found


def translate(definitions: pathlib.Path, rosidl_dir: pathlib.Path):
    """Every package's .msg and .srv files through `rosidl translate --to idl`."""
    for package in sorted(p for p in definitions.iterdir() if p.is_dir()):
        files = sorted(str(f.relative_to(package)) for f in package.glob("*/*") if f.suffix in (".msg", ".srv"))
        done = subprocess.run(["rosidl", "translate", "--to", "idl", "-o", str(rosidl_dir / package.name),
                               package.name] + [f"{package}:{f}" for f in files], capture_output=True, text=True)
        if done.returncode != 0:
            raise SystemExit(f"ros2_dds_idl: rosidl translate {package.name}: {done.stdout}{done.stderr}")


def main(definitions: str, work_dir: str, out: str, names) -> int:
    base = pathlib.Path(work_dir) / "rosidl"
    translate(pathlib.Path(definitions), base)
    ordered, seen = [], set()

    def visit(name):  # every type after the types it uses
        if name in seen:
            return
        seen.add(name)
        for structure, is_service in structures(base, name):
            for m in structure.members:
                t = m.type.value_type if isinstance(m.type, d.AbstractNestedType) else m.type
                if isinstance(t, d.NamespacedType):
                    visit("/".join(list(t.namespaces) + [t.name]))
            ordered.append((structure, is_service))

    for name in names:
        visit(name)
    lines = ["// Generated by idl/ros2_dds_idl.py from ROS 2's definitions (idl/ros2/, through rosidl translate):",
             "// the types as ROS 2's middlewares put them on the wire. Do not edit."]
    for structure, is_service in ordered:
        t = structure.namespaced_type
        lines.append("")
        lines += [f"module {n} {{" for n in t.namespaces] + ["module dds_ {", f"struct {t.name}_ {{"]
        lines += ["  " + h for h in (HEADER if is_service else [])]
        lines += ["  " + member_text(m) for m in structure.members]
        lines += ["};"] + ["};"] * (len(t.namespaces) + 1)
    text = "\n".join(lines) + "\n"
    path = pathlib.Path(out)
    if not path.exists() or path.read_text() != text:
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text(text)
    return 0


if __name__ == "__main__":
    if len(sys.argv) < 5:
        raise SystemExit(__doc__)
    sys.exit(main(sys.argv[1], sys.argv[2], sys.argv[3], sys.argv[4:]))
