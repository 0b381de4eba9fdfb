"""The package's stubs (hapticd/_hapticd.pyi, its value classes generated from idl/hapticd_wire.toml) say what the
extension module has: every attribute a stub class annotates exists on the module's class, and every data attribute
of a value class is in its stub (an attribute added to one and not the other fails here)."""
import ast
import inspect
import os

import hapticd
from hapticd import _hapticd

STUBS = os.path.join(os.path.dirname(hapticd.__file__), "_hapticd.pyi")
VALUE_CLASSES = ("LoopSummary", "SchemeInfo", "DeviceInfo", "DeviceState", "GroupInfo", "GroupState", "Event",
                 "Telemetry", "CycleRecord", "FaultReport", "SceneObject", "SceneContact")


def stub_classes():
    tree = ast.parse(open(STUBS).read())
    classes = {}
    for node in tree.body:
        if isinstance(node, ast.ClassDef):
            names = {n.target.id for n in node.body if isinstance(n, ast.AnnAssign)}
            names |= {t.id for n in node.body if isinstance(n, ast.Assign) for t in n.targets}
            classes[node.name] = names
    return classes


def data_attributes(cls):
    """The module class's read-only attributes (properties), not its methods."""
    return {name for name, value in inspect.getmembers(cls) if not name.startswith("_") and isinstance(value, property)}


def test_every_stubbed_value_class_attribute_exists_and_every_attribute_is_stubbed():
    stubs = stub_classes()
    for name in VALUE_CLASSES:
        assert name in stubs, f"{name} has no stub"
        real = data_attributes(getattr(_hapticd, name))
        assert stubs[name] - real == set(), f"{name}: stubbed but not in the module: {stubs[name] - real}"
        assert real - stubs[name] == set(), f"{name}: in the module but not stubbed: {real - stubs[name]}"


def test_the_enums_stubs_list_the_module_enums_values():
    stubs = stub_classes()
    for name in ("Mode", "EventKind"):
        real = set(getattr(_hapticd, name).__members__)
        assert stubs[name] == real, f"{name}: stub {sorted(stubs[name])}, module {sorted(real)}"
