#!/usr/bin/env python3
"""Generates every language's form of hapticd's wire types from the one table, idl/hapticd_wire.toml (its header says
what comes out and docs/wire-types.md why). Standard library only (tomllib: Python 3.11).

Usage: generate_wire.py TABLE IDL_TEMPLATE PYI_TEMPLATE OUT_DIR
A file is rewritten only when its text changes (nothing rebuilds for nothing)."""
from __future__ import annotations

import re
import sys
import tomllib
from dataclasses import dataclass, field
from pathlib import Path

HEADER = "generated from idl/hapticd_wire.toml by idl/generate_wire.py: edit the table, not this file"


class TableError(Exception):
    pass


@dataclass
class Field:
    name: str
    type: str
    doc: str
    idl: str | None  # the DDS member's name, None: not on DDS
    c: bool
    cpp: bool
    custom: bool
    bound: str | None
    json: str | None
    idl_key: bool
    py: str | None
    py_custom: bool


@dataclass
class Struct:
    name: str
    doc: str
    idl: str | None
    c: str | None
    cpp: str | None
    in_place: bool
    json: bool
    fields: list[Field]
    py_extra: list[str] = field(default_factory=list)


@dataclass
class Enum:
    name: str
    doc: str
    idl: str
    idl_prefix: str
    c: str
    c_prefix: str
    values: list[tuple[str, str]]
    py: bool


@dataclass
class Table:
    constants: dict[str, int]
    enums: dict[str, Enum]
    structs: dict[str, Struct]

    def count(self, text: str) -> int:
        if text.isdigit():
            return int(text)
        if text not in self.constants:
            raise TableError(f"unknown constant '{text}'")
        return self.constants[text]


FIELD_OPTIONS = {"idl", "c", "cpp", "custom", "bound", "json", "idl_key", "py", "py_custom"}
SCALARS = {"f64", "u64", "i64", "i32", "u32", "bool"}
VALUES = {"name", "text", "vec3", "pose", "twist", "wrench", "vec6", "joints"}


def read_table(path: Path) -> Table:
    raw = tomllib.loads(path.read_text())
    table = Table(dict(raw.get("constants", {})), {}, {})
    for name, e in raw.get("enum", {}).items():
        values = [(v[0], v[1]) for v in e["values"]]
        table.enums[name] = Enum(name, e.get("doc", ""), e["idl"], e["idl_prefix"], e["c"], e["c_prefix"], values,
                                 e.get("py", True))
    for name, s in raw.get("struct", {}).items():
        fields = []
        for row in s["fields"]:
            if len(row) not in (3, 4):
                raise TableError(f"{name}: a field is [name, type, doc] or [name, type, doc, options]: {row}")
            options = row[3] if len(row) == 4 else {}
            unknown = set(options) - FIELD_OPTIONS
            if unknown:
                raise TableError(f"{name}.{row[0]}: unknown option(s) {sorted(unknown)}")
            idl = options.get("idl", True)
            fields.append(Field(row[0], row[1], row[2], None if idl is False else (row[0] if idl is True else idl),
                                options.get("c", True), options.get("cpp", True), options.get("custom", False),
                                options.get("bound"), options.get("json"), options.get("idl_key", False),
                                options.get("py"), options.get("py_custom", False)))
        table.structs[name] = Struct(name, s.get("doc", ""), s.get("idl"), s.get("c"), s.get("cpp"),
                                     s.get("names") == "in_place", s.get("json", False), fields,
                                     list(s.get("py_extra", [])))
    for s in table.structs.values():
        for f in s.fields:
            base, _ = split_array(f.type)
            if base not in SCALARS | VALUES | {"names"} | set(table.enums) | set(table.structs) and \
                    not base.startswith("char"):
                raise TableError(f"{s.name}.{f.name}: unknown type '{f.type}'")
    return table


def split_array(type_: str) -> tuple[str, str | None]:
    m = re.fullmatch(r"(\w+)\[(\w+)\]", type_)
    return (m.group(1), m.group(2)) if m else (type_, None)


def wrap(text: str, width: int, prefix: str) -> list[str]:
    """The doc text as comment lines of at most `width` characters, each starting with prefix."""
    words, lines, line = text.split(), [], ""
    for w in words:
        if line and len(prefix) + len(line) + 1 + len(w) > width:
            lines.append(prefix + line)
            line = w
        else:
            line = f"{line} {w}" if line else w
    if line:
        lines.append(prefix + line)
    return lines


# ---- the DDS IDL ----
def idl_type(t: Table, f: Field) -> tuple[str, str]:
    """The IDL type and the array suffix of a field."""
    base, n = split_array(f.type)
    simple = {"f64": "double", "u64": "unsigned long long", "i64": "long long", "i32": "long", "u32": "unsigned long",
              "bool": "boolean", "name": "Name", "text": "Text", "vec3": "Vec3", "pose": "Pose", "twist": "Vec6",
              "wrench": "Vec6", "vec6": "Vec6", "joints": "JointArray", "names": "Label"}
    if base in simple:
        type_ = simple[base]
    elif base in t.enums:
        type_ = t.enums[base].idl
    elif base in t.structs and t.structs[base].idl:
        type_ = t.structs[base].idl
    else:
        raise TableError(f"{f.name}: '{f.type}' has no IDL form")
    return type_, f"[{t.count(n)}]" if n else ""


def idl_struct_body(t: Table, s: Struct) -> str:
    lines = []
    for f in s.fields:
        if f.idl is None:
            continue
        type_, suffix = idl_type(t, f)
        decl = f"  {'@key ' if f.idl_key else ''}{type_} {f.idl}{suffix};"
        if f.doc:
            comment = wrap(f.doc, 118 - 34, "")
            lines.append(f"{decl:<32}  // {comment[0]}")
            lines.extend(f"{'':<32}  // {c}" for c in comment[1:])
        else:
            lines.append(decl)
    return "\n".join(lines)


def idl_enum_body(e: Enum) -> str:
    lines = []
    for i, (value, doc) in enumerate(e.values):
        decl = f"  {e.idl_prefix}{value.upper()}{',' if i + 1 < len(e.values) else ''}"
        if doc:
            comment = wrap(doc, 118 - 26, "")
            lines.append(f"{decl:<24}  // {comment[0]}")
            lines.extend(f"{'':<24}  // {c}" for c in comment[1:])
        else:
            lines.append(decl)
    return "\n".join(lines)


def make_idl(t: Table, template: str) -> str:
    def replace(m: re.Match) -> str:
        kind, name = m.group(1), m.group(2)
        if kind == "struct":
            matches = [s for s in t.structs.values() if s.idl == name]
            if not matches:
                raise TableError(f"the IDL template names struct {name}, which the table has not")
            return idl_struct_body(t, matches[0])
        if kind == "enum":
            matches = [e for e in t.enums.values() if e.idl == name]
            if not matches:
                raise TableError(f"the IDL template names enum {name}, which the table has not")
            return idl_enum_body(matches[0])
        if name not in t.constants:
            raise TableError(f"the IDL template names constant {name}, which the table has not")
        return str(t.constants[name])

    text = re.sub(r"^ *@@(struct|enum|constant) (\w+)@@$", replace, template, flags=re.M)
    text = re.sub(r"@@(constant) (\w+)@@", replace, text)
    if "@@" in text:
        raise TableError("the IDL template has a placeholder left: " + text[text.index("@@"):][:60])
    return f"// {HEADER} (and idl/hapticd_msg.idl.in).\n" + text


# ---- C ----
def c_decl(t: Table, f: Field) -> str:
    base, n = split_array(f.type)
    count = f"[{t.count(n)}]" if n else ""
    limit = {"MAX_JOINTS": "HAPTICD_MAX_JOINTS", "MAX_SCHEMES": "HAPTICD_MAX_SCHEMES", "MAX_VALUES": "HAPTICD_MAX_VALUES",
             "MAX_GROUP_DEVICES": "HAPTICD_MAX_GROUP_DEVICES", "MAX_HISTORY": "HAPTICD_MAX_FAULT_RECORDS",
             "REJECT_REASONS": "HAPTICD_REJECT_REASONS"}
    if n and n in limit:
        count = f"[{limit[n]}]"
    simple = {"f64": "double", "u64": "uint64_t", "i64": "int64_t", "i32": "int32_t", "u32": "uint32_t",
              "bool": "int32_t", "vec3": "hapticd_vec3", "pose": "hapticd_pose", "twist": "hapticd_twist",
              "wrench": "hapticd_wrench"}
    if base in simple:
        return f"{simple[base]} {f.name}{count};"
    if base == "name":
        return f"char {f.name}{count}[HAPTICD_NAME_SIZE];"
    if base == "names":
        return f"char {f.name}{count}[HAPTICD_NAME_SIZE];"
    if base == "text":
        return f"char {f.name}{count}[HAPTICD_MESSAGE_SIZE];"
    if base == "char":
        return f"char {f.name}{count};"
    if base == "vec6":
        return f"double {f.name}[6];"
    if base == "joints":
        return f"double {f.name}[HAPTICD_MAX_JOINTS];"
    if base in t.enums:
        return f"int32_t {f.name}{count}; /* {t.enums[base].c} */"
    if base in t.structs and t.structs[base].c:
        return f"{t.structs[base].c} {f.name}{count};"
    raise TableError(f"{f.name}: '{f.type}' has no C form")


def c_doc(doc: str) -> str:
    return doc.replace("*/", "* /")


def make_c_header(t: Table) -> str:
    out = [f"/* hapticd's C API: its value types ({HEADER}).",
           " * Included by hapticd/client.h, which says how they are used. */",
           "#ifndef HAPTICD_CLIENT_TYPES_H", "#define HAPTICD_CLIENT_TYPES_H", "", "#include <stdint.h>", "",
           f"#define HAPTICD_NAME_SIZE {t.constants['NAME_SIZE']} /* names: up to "
           f"{t.constants['NAME_SIZE'] - 1} characters and a terminating zero */",
           f"#define HAPTICD_MESSAGE_SIZE {t.constants['MESSAGE_SIZE']} /* messages: longer ones are cut */",
           f"#define HAPTICD_MAX_JOINTS {t.constants['MAX_JOINTS']}",
           f"#define HAPTICD_MAX_VALUES {t.constants['MAX_VALUES']} /* values of a request or reply */",
           f"#define HAPTICD_MAX_GROUP_DEVICES {t.constants['MAX_GROUP_DEVICES']} /* devices of a group */",
           f"#define HAPTICD_MAX_SCHEMES {t.constants['MAX_SCHEMES']} /* schemes listed in a device's description */",
           f"#define HAPTICD_MAX_FAULT_RECORDS {t.constants['MAX_HISTORY']} /* cycles kept of a fault report */",
           f"#define HAPTICD_REJECT_REASONS {t.constants['REJECT_REASONS']}", "",
           "/* ---- spatial values (world frame; twists and wrenches at the handle point) ---- */",
           "typedef struct hapticd_vec3 {", "  double x, y, z;", "} hapticd_vec3;",
           "typedef struct hapticd_quat {", "  double w, x, y, z;", "} hapticd_quat;",
           "typedef struct hapticd_pose {", "  hapticd_vec3 position; /* m */", "  hapticd_quat orientation;",
           "} hapticd_pose;", "typedef struct hapticd_twist {", "  hapticd_vec3 linear;  /* m/s */",
           "  hapticd_vec3 angular; /* rad/s */", "} hapticd_twist;", "typedef struct hapticd_wrench {",
           "  hapticd_vec3 force;  /* N */", "  hapticd_vec3 torque; /* N m */", "} hapticd_wrench;", ""]
    for e in t.enums.values():
        out.append(f"/* {c_doc(e.doc)} */")
        out.append(f"typedef enum {e.c} {{")
        for i, (value, doc) in enumerate(e.values):
            line = f"  {e.c_prefix}{value.upper()} = {i}{',' if i + 1 < len(e.values) else ''}"
            out.append(line + (f" /* {c_doc(doc)} */" if doc else ""))
        out.append(f"}} {e.c};")
        out.append("")
    for s in t.structs.values():
        if not s.c:
            continue
        out.append(f"/* {c_doc(s.doc)} */")
        out.append(f"typedef struct {s.c} {{")
        for f in s.fields:
            if not f.c:
                continue
            decl = "  " + c_decl(t, f)
            out.append(decl + (f" /* {c_doc(f.doc)} */" if f.doc and "/*" not in decl else ""))
        out.append(f"}} {s.c};")
        out.append("")
    out.append("#endif /* HAPTICD_CLIENT_TYPES_H */")
    return "\n".join(out) + "\n"


def make_c_layout(t: Table) -> str:
    """The layout program: the size of every C struct and the offset of every field of the table's."""
    out = [f"/* Prints the C API's struct layouts, one \"name value\" per line ({HEADER}): the ABI test compares",
           " * them with the committed clients/c/abi/hapticd_c.layout, the C# test its struct sizes. */",
           "#include <hapticd/client.h>", "#include <stddef.h>", "#include <stdio.h>", "",
           "#define SIZE(T) printf(\"sizeof %s %zu\\n\", #T, sizeof(T))",
           "#define OFFSET(T, F) printf(\"offsetof %s.%s %zu\\n\", #T, #F, offsetof(T, F))", "", "int main(void) {"]
    for name in ("hapticd_vec3", "hapticd_quat", "hapticd_pose", "hapticd_twist", "hapticd_wrench"):
        out.append(f"  SIZE({name});")
    for s in t.structs.values():
        if s.c:
            out.append(f"  SIZE({s.c});")
    for name in ("hapticd_client_options", "hapticd_engine_options", "hapticd_engine_end"):
        out.append(f"  SIZE({name});")
    for s in t.structs.values():
        if s.c:
            out.extend(f"  OFFSET({s.c}, {f.name});" for f in s.fields if f.c)
    # The option structs are the C API's own (hapticd/client.h), not wire types: their fields by hand here.
    for struct, names in (("hapticd_client_options", "domain_id cyclone_config network command_deadline_s"),
                          ("hapticd_engine_options", "name device group wait_s server_timeout_s duration_s "
                                                     "wait_for_server"),
                          ("hapticd_engine_end", "exit_code message")):
        out.extend(f"  OFFSET({struct}, {n});" for n in names.split())
    out += ["  return 0;", "}"]
    return "\n".join(out) + "\n"


# ---- C# ----
def pascal(name: str) -> str:
    return "".join(p[:1].upper() + p[1:] for p in name.split("_"))


def cs_fields(t: Table, s: Struct) -> tuple[list[str], list[str]]:
    """The C# fields (field for field as the C struct) and the accessors of names, texts and enums."""
    decls, accessors = [], []
    for f in s.fields:
        if not f.c:
            continue
        base, n = split_array(f.type)
        count = t.count(n) if n else None
        simple = {"f64": "double", "u64": "ulong", "i64": "long", "i32": "int", "u32": "uint", "bool": "int",
                  "vec3": "Vec3", "pose": "Pose", "twist": "Twist", "wrench": "Wrench"}
        size = {"name": t.constants["NAME_SIZE"], "names": t.constants["NAME_SIZE"],
                "text": t.constants["MESSAGE_SIZE"]}.get(base)
        prop = pascal(f.name)
        if prop == pascal(s.name):  # C# refuses a member named as its type
            prop += "Text"
        if base in simple and count is None:
            decls.append(f"public {simple[base]} {f.name};")
        elif base in ("f64", "u64", "i64", "i32", "u32") and count:
            decls.append(f"public fixed {simple[base]} {f.name}[{count}];")
        elif base in ("name", "text") and count is None:
            decls.append(f"public fixed byte {f.name}[{size}];")
            accessors.append(f"public string {prop} {{ get {{ fixed (byte* p = {f.name}) return Text.Of(p, {size}); }} }}")
        elif base == "names":
            decls.append(f"public fixed byte {f.name}[{count} * {size}];")
            single = prop[:-1] if prop.endswith("s") else prop
            accessors.append(f"public string {single}(int i) {{ if (i < 0 || i >= {count}) throw new "
                             f"ArgumentOutOfRangeException(\"i\"); fixed (byte* p = {f.name}) return "
                             f"Text.Of(p + {size} * i, {size}); }}")
        elif base == "char":
            decls.append(f"public fixed byte {f.name}[{count}];")
            accessors.append(f"public string {prop} {{ get {{ fixed (byte* p = {f.name}) return Text.Of(p, {count}); }} }}")
        elif base == "vec6":
            decls.append(f"public fixed double {f.name}[6];")
        elif base == "joints":
            decls.append(f"public fixed double {f.name}[{t.constants['MAX_JOINTS']}];")
        elif base in t.enums:
            decls.append(f"public int {f.name};  // {pascal(base)}")
            accessors.append(f"public {base} {prop} {{ get {{ return ({base}){f.name}; }} }}")
        elif base in t.structs:
            cs = t.structs[base].name
            if count is None:
                decls.append(f"public {cs} {f.name};")
            else:
                # No fixed buffer of structs in C#: one field per element, in order (the C array's layout).
                decls.extend(f"public {cs} {f.name}_{i};" for i in range(count))
                single = prop[:-1] if prop.endswith("s") else prop
                accessors.append(f"public {cs} {single}(int i) {{ if (i < 0 || i >= {count}) throw new "
                                 f"ArgumentOutOfRangeException(\"i\"); fixed ({cs}* p = &{f.name}_0) return p[i]; }}")
        else:
            raise TableError(f"{s.name}.{f.name}: '{f.type}' has no C# form")
    return decls, accessors


def make_csharp(t: Table) -> str:
    out = [f"// hapticd's C API value types for C# ({HEADER}).",
           "// Field for field the C structs of hapticd/client_types.h (blittable: fixed buffers, no marshalled",
           "// strings); Native.cs adds their helpers in the other part of each partial struct.",
           "using System;", "using System.Runtime.InteropServices;", "", "namespace Hapticd", "{",
           "    public static partial class Limits", "    {",
           f"        public const int NameSize = {t.constants['NAME_SIZE']}, MessageSize = {t.constants['MESSAGE_SIZE']}, "
           f"MaxJoints = {t.constants['MAX_JOINTS']}, MaxValues = {t.constants['MAX_VALUES']},",
           f"                         MaxGroupDevices = {t.constants['MAX_GROUP_DEVICES']}, MaxSchemes = "
           f"{t.constants['MAX_SCHEMES']}, MaxFaultRecords = {t.constants['MAX_HISTORY']}, "
           f"RejectReasons = {t.constants['REJECT_REASONS']};", "    }", ""]
    for e in t.enums.values():
        values = ", ".join(f"{pascal(v)} = {i}" for i, (v, _) in enumerate(e.values))
        out.append(f"    // {e.c}: {e.doc}")
        out.append(f"    public enum {e.name} {{ {values} }}")
        out.append("")
    for s in t.structs.values():
        if not s.c:
            continue
        decls, accessors = cs_fields(t, s)
        out.append(f"    // {s.c}: {s.doc}")
        out.append("    [StructLayout(LayoutKind.Sequential)]")
        out.append(f"    public unsafe partial struct {s.name}")
        out.append("    {")
        out.extend(f"        {d}" for d in decls)
        if accessors:
            out.append("")
            out.extend(f"        {a}" for a in accessors)
        out.append("    }")
        out.append("")
    out.append("}")
    return "\n".join(out) + "\n"


# ---- Python stubs ----
def py_type(t: Table, s: Struct, f: Field) -> str:
    if f.py:
        return f.py
    base, n = split_array(f.type)
    simple = {"f64": "float", "u64": "int", "i64": "int", "i32": "int", "u32": "int", "bool": "bool", "name": "str",
              "text": "str", "vec3": "Vector", "pose": "Pose", "twist": "Twist", "wrench": "Wrench",
              "vec6": "Vector", "joints": "Vector", "names": "str"}
    if base in simple:
        type_ = simple[base]
    elif base in t.enums or base in t.structs:
        type_ = base
    else:
        raise TableError(f"{s.name}.{f.name}: '{f.type}' has no Python form")
    return f"list[{type_}]" if n else type_


def make_pyi(t: Table, template: str) -> str:
    parts = []
    for e in t.enums.values():
        if not e.py:
            continue
        parts.append(f"class {e.name}(enum.Enum):")
        parts.append(f'    """{e.doc}"""')
        parts.extend(f"    {v.upper()} = ..." for v, _ in e.values)
        parts.append("")
    for s in t.structs.values():
        if not s.cpp:
            continue
        parts.append(f"class {s.name}:")
        parts.append(f'    """{s.doc}"""')
        for f in s.fields:
            if f.cpp:
                line = f"    {f.name}: {py_type(t, s, f)}"
                parts.append(line + (f"  # {f.doc}" if f.doc and len(line) + len(f.doc) < 116 else ""))
        parts.extend(f"    {extra}" for extra in s.py_extra)
        parts.append("")
    marker = "# @@value types@@\n"
    if marker not in template:
        raise TableError("the stub template has no '# @@value types@@' line")
    return template.replace(marker, f"# ---- the value types ({HEADER}) ----\n" + "\n".join(parts))


# ---- C++: the copies between the forms ----
def dds_name(s: Struct) -> str:
    return f"hapticd_msg_{s.idl}"


def make_from_msg(t: Table) -> str:
    """DDS -> the client library's C++ types (clients/lib/src/wire.cpp includes it): every field but the custom."""
    out = [f"// {HEADER}.", "// DDS samples -> the client library's types, field by field (the custom fields are",
           "// wire.cpp's). Included in wire.cpp's unnamed namespace, after the get() helpers."]
    for s in t.structs.values():
        if not (s.idl and s.cpp):
            continue
        noexcept = " noexcept" if s.in_place or all(split_array(f.type)[0] not in ("name", "text", "names")
                                                      for f in s.fields) else ""
        out.append(f"void copy_fields(const {dds_name(s)}& in, {s.cpp}& out){noexcept} {{")
        for f in s.fields:
            if f.custom or not f.cpp or f.idl is None:
                continue
            base, n = split_array(f.type)
            if f.bound:
                limit = f.bound if f.bound.isdigit() else f"hapticd_msg_{f.bound}"
                out.append(f"  out.{f.name} = bounded(in.{f.idl}, {limit});")
            elif base == "joints":
                out.append(f"  get_joints(in.{f.idl}, out.dof, out.{f.name});")
            elif base in t.structs:
                out.append(f"  copy_fields(in.{f.idl}, out.{f.name});")
            else:
                out.append(f"  get(in.{f.idl}, out.{f.name});")
        out.append("}")
    return "\n".join(out) + "\n"


def make_to_c(t: Table) -> str:
    """The client library's C++ types -> the C structs (clients/c/src/c_values.cpp includes it)."""
    out = [f"// {HEADER}.", "// The client library's types -> the C structs, field by field (the custom fields are",
           "// c_values.cpp's). Included in c_values.cpp's unnamed namespace, after the put() helpers."]
    for s in t.structs.values():
        if not (s.c and s.cpp):
            continue
        out.append(f"void copy_fields(const client::{s.cpp}& in, {s.c}& out) noexcept {{")
        for f in s.fields:
            if f.custom or not f.cpp or not f.c:
                continue
            base, _ = split_array(f.type)
            if base in t.structs:
                out.append(f"  copy_fields(in.{f.name}, out.{f.name});")
            else:
                out.append(f"  put(in.{f.name}, out.{f.name});")
        out.append("}")
    return "\n".join(out) + "\n"


def cpp_string(text: str) -> str:
    return '"' + text.replace("\\", "\\\\").replace('"', '\\"') + '"'


def make_python_fields(t: Table) -> str:
    """The Python classes of the C++ value types (python/src/bind_client.cpp includes it): bind_<Type>(module) makes
    the class with the table's doc and its read-only attributes and returns it for the custom ones."""
    out = [f"// {HEADER}.", "// The value classes and enums of the Python module (the custom attributes are bind_client.cpp's).",
           "// Included in bind_client.cpp's unnamed namespace."]
    for e in t.enums.values():
        if not e.py:
            continue
        out.append(f"void bind_{e.name}(py::module_& m) {{")
        out.append(f"  py::enum_<{e.name}>(m, \"{e.name}\", {cpp_string(e.doc)})")
        out.extend(f"      .value(\"{v.upper()}\", {e.name}::{v})" for v, _ in e.values)
        out[-1] += ";"
        out.append("}")
    for s in t.structs.values():
        if not s.cpp:
            continue
        out.append(f"py::class_<{s.cpp}> bind_{s.cpp}(py::module_& m) {{")
        out.append(f"  py::class_<{s.cpp}> c(m, \"{s.cpp}\", {cpp_string(s.doc)});")
        for f in s.fields:
            if not f.cpp or f.py_custom:
                continue
            base, n = split_array(f.type)
            doc = cpp_string(f.doc)
            if base == "joints":
                out.append(f'  c.def_property_readonly("{f.name}", [](const {s.cpp}& v) {{ return joint_array(v.{f.name}); '
                           f'}}, {doc});')
            elif base == "vec3":
                out.append(f'  c.def_property_readonly("{f.name}", [](const {s.cpp}& v) {{ return Eigen::Vector3d(v.{f.name}); '
                           f'}}, {doc});')
            elif base == "name" and s.in_place:
                out.append(f'  c.def_property_readonly("{f.name}", [](const {s.cpp}& v) {{ return v.{f.name}.str(); }}, '
                           f'{doc});')
            else:
                out.append(f'  c.def_readonly("{f.name}", &{s.cpp}::{f.name}, {doc});')
        out.append("  return c;")
        out.append("}")
    return "\n".join(out) + "\n"


def make_socket_json(t: Table) -> str:
    """The engine socket's JSON writers (server/src/doors/socket/socket_messages.cpp includes it)."""
    out = [f"// {HEADER}.", "// The engine socket's JSON for DDS samples: each struct's sections, member by member, and",
           "// the enums' names. Included in socket_messages.cpp's unnamed namespace, after the json_*() helpers."]
    for e in t.enums.values():
        out.append(f"[[maybe_unused]] std::string_view json_name(hapticd_msg_{e.idl} value) noexcept {{")
        out.append("  switch (value) {")
        for v, _ in e.values:
            out.append(f"    case hapticd_msg_{e.idl_prefix}{v.upper()}:")
            out.append(f'      return "{v}";')
        out.append("  }")
        out.append('  return "other";')
        out.append("}")
    for s in t.structs.values():
        if not s.json:
            continue
        sections: dict[str, list[tuple[Field, list[str]]]] = {}
        for f in s.fields:
            if f.json:
                section, _, keys = f.json.partition(":")
                sections.setdefault(section, []).append((f, keys.split(",")))
        names = ", ".join('"' + k + '"' for k in sections)
        out.append(f"// {names}: the members of {s.idl} the socket shows.")
        out.append(f"void append_json(std::string& out, const {dds_name(s)}& s) {{")
        for i, (section, members) in enumerate(sections.items()):
            out.append(f'  out += "{"," if i else ""}\\"{section}\\":{{";')
            out.append("  bool first = true;" if i == 0 else "  first = true;")
            for f, keys in members:
                base, _ = split_array(f.type)
                value = f"s.{f.idl}"
                if base in ("name", "text"):
                    writes = [(keys[0], f"append_string(out, dds::text_of({value}))")]
                elif base in ("u64", "i64", "i32", "u32"):
                    writes = [(keys[0], f"append_integer(out, static_cast<std::int64_t>({value}))")]
                elif base == "bool":
                    writes = [(keys[0], f"out += {value} ? \"true\" : \"false\"")]
                elif base == "f64":
                    writes = [(keys[0], f"append_number(out, {value})")]
                elif base == "pose":
                    writes = [(keys[0], f"json_vector3(out, {value}.position)")]
                    if len(keys) > 1:
                        writes.append((keys[1], f"json_quaternion(out, {value}.orientation)"))
                elif base in ("twist", "wrench"):
                    writes = [(keys[0], f"json_vector3(out, {value})")]
                    if len(keys) > 1:
                        writes.append((keys[1], f"json_vector3(out, {value} + 3)"))
                elif base == "vec3":
                    writes = [(keys[0], f"json_vector3(out, {value})")]
                elif base in t.enums:
                    writes = [(keys[0], f"append_string(out, json_name({value}))")]
                else:
                    raise TableError(f"{s.name}.{f.name}: '{f.type}' has no JSON form")
                for key, write in writes:
                    out.append(f'  json_member(out, first, "{key}");')
                    out.append(f"  {write};")
            out.append("  out += '}';")
        out.append("}")
    return "\n".join(out) + "\n"


def write(path: Path, text: str) -> None:
    if path.exists() and path.read_text() == text:
        return
    path.parent.mkdir(parents=True, exist_ok=True)
    tmp = path.with_suffix(path.suffix + ".tmp")
    tmp.write_text(text)
    tmp.replace(path)


def main(argv: list[str]) -> int:
    if len(argv) != 5:
        print(__doc__, file=sys.stderr)
        return 2
    table_path, idl_template, pyi_template, out = Path(argv[1]), Path(argv[2]), Path(argv[3]), Path(argv[4])
    try:
        t = read_table(table_path)
        outputs = {
            "idl/hapticd_msg.idl": make_idl(t, idl_template.read_text()),
            "include/hapticd/client_types.h": make_c_header(t),
            "c/layout.c": make_c_layout(t),
            "csharp/NativeTypes.g.cs": make_csharp(t),
            "python/_hapticd.pyi": make_pyi(t, pyi_template.read_text()),
            "cpp/hapticd_wire/from_msg.inc": make_from_msg(t),
            "cpp/hapticd_wire/to_c.inc": make_to_c(t),
            "cpp/hapticd_wire/python_fields.inc": make_python_fields(t),
            "cpp/hapticd_wire/socket_json.inc": make_socket_json(t),
        }
    except (TableError, tomllib.TOMLDecodeError, KeyError, OSError) as e:
        print(f"{table_path}: {e}", file=sys.stderr)
        return 1
    for name, text in outputs.items():
        write(out / name, text)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
