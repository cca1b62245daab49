"""The type stubs (python/vdtnav/__init__.pyi) against the built module, so that they cannot drift.

Parses the stub with `ast` and checks, against vdtnav._vdtnav as built:
- every public name the module exports is declared in the stub, and every public name the stub
  declares exists (but the 3D and the bag names, in builds without those front ends);
- every class's public methods and properties (and __init__ / __len__ where bound) are declared
  in the stub's class, nothing more, with the same base classes;
- every function's and method's parameter names, keyword-only marker and defaults match the
  pybind11 signature (a literal default in the stub must equal the bound one);
- the attributes writable at run time are the ones writable in the stub;
- the submodule _timing's functions are declared in the stub's _TimingModule.
"""
import ast
import pathlib

import pytest

import vdtnav

core = vdtnav._vdtnav
STUB = pathlib.Path(__file__).resolve().parents[1] / "vdtnav" / "__init__.pyi"

# Bound only in some builds: with the 3D front ends (pcl; VDTNAV_PYTHON_3D_FILES) and
# with the ROS front end (VDTNAV_PYTHON_ROS). Each group is all there or all absent.
OPTIONAL = [
    {"OdometryStep3", "localize3d", "Localizer3D", "make_localizer3d", "read_point_cloud",
     "GlobalLocalization3", "global_localize3d"},
    {"bag_topics", "read_bag_scans", "read_bag_clouds"},
]
# Dunder methods a class may bind that the stub must then declare.
DUNDERS = {"__init__", "__len__", "__iter__", "__getitem__", "__contains__", "__call__"}


# ----------------------------------------------------------------------------------------------
# The stub


class StubClass:
    def __init__(self, node):
        self.node = node
        self.bases = [b.id if isinstance(b, ast.Name) else ast.unparse(b) for b in node.bases]
        self.functions = {}  # name -> FunctionDef (the getter of a property, the method)
        self.properties = set()
        self.writable = set()  # plain annotated attributes and properties with a setter
        self.attributes = set()
        for item in node.body:
            if isinstance(item, ast.FunctionDef):
                decorators = [ast.unparse(d) for d in item.decorator_list]
                if any(d.endswith(".setter") for d in decorators):
                    self.writable.add(item.name)
                    continue
                self.functions[item.name] = item
                if "property" in decorators:
                    self.properties.add(item.name)
            elif isinstance(item, ast.AnnAssign) and isinstance(item.target, ast.Name):
                self.attributes.add(item.target.id)
                self.writable.add(item.target.id)

    @property
    def members(self):
        return set(self.functions) | self.attributes

    def is_static(self, name):
        return any(ast.unparse(d) == "staticmethod" for d in self.functions[name].decorator_list)


def parse_stub():
    tree = ast.parse(STUB.read_text(encoding="utf-8"), filename=str(STUB))
    functions, classes, names = {}, {}, set()
    annotations = {}
    for node in tree.body:
        if isinstance(node, ast.FunctionDef):
            functions[node.name] = node
            names.add(node.name)
        elif isinstance(node, ast.ClassDef):
            classes[node.name] = StubClass(node)
            names.add(node.name)
        elif isinstance(node, ast.AnnAssign) and isinstance(node.target, ast.Name):
            names.add(node.target.id)
            annotations[node.target.id] = node
        elif isinstance(node, ast.Assign):
            names.update(t.id for t in node.targets if isinstance(t, ast.Name))
    return functions, classes, names, annotations


FUNCTIONS, CLASSES, NAMES, ANNOTATIONS = parse_stub()


def stub_parameters(fn, drop_self):
    """[(name, kind, default text or None)], kind 'pos' or 'kw'."""
    a = fn.args
    positional = a.posonlyargs + a.args
    defaults = [None] * (len(positional) - len(a.defaults)) + list(a.defaults)
    out = [(p.arg, "pos", d) for p, d in zip(positional, defaults)]
    out += [(p.arg, "kw", d) for p, d in zip(a.kwonlyargs, a.kw_defaults)]
    if drop_self and out and out[0][0] == "self":
        out = out[1:]
    return [(n, k, None if d is None else ast.unparse(d)) for n, k, d in out]


# ----------------------------------------------------------------------------------------------
# The module: pybind11's signatures (the first line of each docstring)


def split_top_level(text):
    parts, depth, quote, start = [], 0, None, 0
    for i, c in enumerate(text):
        if quote:
            if c == quote and text[i - 1] != "\\":
                quote = None
        elif c in "'\"":
            quote = c
        elif c in "([{<":
            depth += 1
        elif c in ")]}>":
            depth -= 1
        elif c == "," and depth == 0:
            parts.append(text[start:i].strip())
            start = i + 1
    if text[start:].strip():
        parts.append(text[start:].strip())
    return parts


def runtime_parameters(obj, name):
    """[(name, kind, default text or None)] from a pybind11 function's docstring signature, the
    leading self dropped; None when there is no single signature."""
    doc = getattr(obj, "__doc__", None) or ""
    line = doc.lstrip().split("\n", 1)[0]
    if not line.startswith(name + "("):
        return None
    depth, end = 0, None
    for i, c in enumerate(line):
        if c == "(":
            depth += 1
        elif c == ")":
            depth -= 1
            if depth == 0:
                end = i
                break
    out, kind = [], "pos"
    for p in split_top_level(line[len(name) + 1 : end]):
        if p == "*":
            kind = "kw"
            continue
        if p == "/":
            continue
        head, _, default = p.partition("=")
        pname = head.split(":", 1)[0].strip()
        out.append((pname, kind, default.strip() or None))
    if out and out[0][0] == "self":
        out = out[1:]
    return out


def public(names):
    return sorted(n for n in names if not n.startswith("_"))


def exported():
    return public(dir(core))


def runtime_classes():
    return [n for n in exported() if isinstance(getattr(core, n), type)]


def runtime_functions():
    return [n for n in exported() if not isinstance(getattr(core, n), type)]


def compare_parameters(where, stub_fn, runtime_obj, name, drop_self):
    runtime = runtime_parameters(runtime_obj, name)
    assert runtime is not None, f"{where}: no pybind11 signature in its docstring"
    stub = stub_parameters(stub_fn, drop_self)
    assert [(n, k) for n, k, _ in stub] == [(n, k) for n, k, _ in runtime], (
        f"{where}: parameters (name, positional/keyword-only) differ:\n"
        f"  stub:   {[(n, k) for n, k, _ in stub]}\n  module: {[(n, k) for n, k, _ in runtime]}"
    )
    for (n, _, sd), (_, _, rd) in zip(stub, runtime):
        assert (sd is None) == (rd is None), f"{where}: {n}: default in stub {sd}, module {rd}"
        if sd is not None and sd != "...":
            value = ast.literal_eval(sd)
            assert repr(value) == rd, f"{where}: {n}: default {sd} in the stub, {rd} bound"


# ----------------------------------------------------------------------------------------------
# The tests


def test_stub_parses_and_has_docstrings():
    tree = ast.parse(STUB.read_text(encoding="utf-8"))
    assert ast.get_docstring(tree)
    for name in public(set(FUNCTIONS) | set(CLASSES)):
        node = FUNCTIONS.get(name) or CLASSES[name].node
        assert ast.get_docstring(node), f"{name}: no docstring in the stub"


def test_every_export_is_in_the_stub():
    missing = [n for n in exported() if n not in NAMES]
    assert not missing, f"exported by vdtnav._vdtnav but not declared in {STUB.name}: {missing}"
    assert "__version__" in NAMES and isinstance(vdtnav.__version__, str)


def test_the_stub_declares_nothing_the_module_lacks():
    declared = public(NAMES)
    extra = [n for n in declared if not hasattr(core, n)]
    for group in OPTIONAL:
        present = sorted(n for n in group if hasattr(core, n))
        if not present:  # a build without that front end
            extra = [n for n in extra if n not in group]
        else:
            assert present == sorted(group), f"only part of an optional group is bound: {present}"
    assert not extra, f"declared in {STUB.name} but not exported: {extra}"


def test_the_package_reexports_the_core():
    for n in exported():
        assert getattr(vdtnav, n) is getattr(core, n), n


@pytest.mark.parametrize("name", runtime_classes())
def test_class_members(name):
    cls = getattr(core, name)
    assert name in CLASSES, f"{name} is a class in the module but no class in the stub"
    stub = CLASSES[name]
    own = vars(cls)
    # pybind11 gives every class an __init__ slot: a bound constructor has a signature.
    bound = {d for d in DUNDERS & set(own) if runtime_parameters(getattr(cls, d), d) is not None}
    runtime = set(public(own)) | bound
    missing = sorted(runtime - stub.members)
    assert not missing, f"{name}: members not declared in the stub: {missing}"
    extra = sorted(m for m in stub.members - runtime if not m.startswith("_") or m in DUNDERS)
    assert not extra, f"{name}: declared in the stub but not in the module: {extra}"
    bases = [b.__name__ for b in cls.__bases__ if b.__name__ not in ("pybind11_object", "object")]
    assert [b for b in stub.bases if b != "object"] == bases, f"{name}: base classes differ"


@pytest.mark.parametrize("name", runtime_classes())
def test_class_signatures_and_writable_attributes(name):
    cls = getattr(core, name)
    stub = CLASSES[name]
    for member, value in vars(cls).items():
        if member not in stub.members or (member.startswith("_") and member not in DUNDERS):
            continue  # test_class_members reports what is missing
        where = f"{name}.{member}"
        if isinstance(value, property):
            writable = value.fset is not None
            assert (member in stub.writable) == writable, (
                f"{where}: {'writable' if writable else 'read-only'} in the module, "
                f"{'writable' if member in stub.writable else 'read-only'} in the stub"
            )
            assert member not in stub.functions or member in stub.properties, (
                f"{where}: a property in the module, a method in the stub"
            )
            continue
        if member not in stub.functions:
            pytest.fail(f"{where}: a method in the module, an attribute in the stub")
        assert member not in stub.properties, f"{where}: a method in the module, a property in the stub"
        static = isinstance(value, staticmethod)
        assert stub.is_static(member) == static, f"{where}: static in one, not in the other"
        fn = getattr(cls, member)
        compare_parameters(where, stub.functions[member], fn, member, drop_self=not static)


@pytest.mark.parametrize("name", runtime_functions())
def test_function_signatures(name):
    obj = getattr(core, name)
    if isinstance(obj, type(core)):  # a submodule: test_timing_submodule
        pytest.skip("submodule")
    assert name in FUNCTIONS, f"{name} is a function in the module but not in the stub"
    compare_parameters(name, FUNCTIONS[name], obj, name, drop_self=False)


def test_timing_submodule():
    # _vdtnav: _CoreModule, whose _timing: _TimingModule declares _timing's functions.
    core_annotation = ANNOTATIONS.get("_vdtnav")
    assert core_annotation is not None, "the stub does not declare _vdtnav"
    core_class = CLASSES[ast.unparse(core_annotation.annotation)]
    timing = next(
        (i for i in core_class.node.body if isinstance(i, ast.AnnAssign) and i.target.id == "_timing"),
        None,
    )
    assert timing is not None, f"{core_class.node.name} does not declare _timing"
    stub = CLASSES[ast.unparse(timing.annotation)]
    runtime = set(public(dir(core._timing)))
    assert runtime == set(public(stub.members)), (
        f"_timing: module {sorted(runtime)}, stub {sorted(public(stub.members))}"
    )
    for name in sorted(runtime):
        compare_parameters(f"_timing.{name}", stub.functions[name], getattr(core._timing, name),
                           name, drop_self=False)
