"""The shipped stubs (cover/__init__.pyi) name exactly what the module defines, with the same
parameters, and every function has a docstring."""

import ast
import pathlib
import re

import cover

STUBS = pathlib.Path(cover.__file__).with_name("__init__.pyi")


def stub_tree():
    return ast.parse(STUBS.read_text())


def params(fn):
    """Parameter names of a stub function (without self), keyword-only marked with '*'."""
    a = fn.args
    names = [p.arg for p in a.posonlyargs + a.args if p.arg != "self"]
    if a.kwonlyargs:
        names += ["*"] + [p.arg for p in a.kwonlyargs]
    return names


def runtime_params(obj):
    """Parameter names from a pybind11 signature line 'name(self: ..., x: ..., *, t: ...) -> ...'."""
    first = obj.__doc__.splitlines()[0]
    inside = first[first.index("(") + 1:first.rindex(") ->")]
    names = []
    depth, current = 0, ""
    for ch in inside + ",":
        if ch in "[(":
            depth += 1
        elif ch in "])":
            depth -= 1
        if ch == "," and depth == 0:
            name = re.split(r"[:=]", current.strip())[0].strip()
            if name and name != "self":
                names.append(name)
            current = ""
        else:
            current += ch
    return names


def test_stubs_and_py_typed_ship_with_the_package():
    assert STUBS.exists()
    assert STUBS.with_name("py.typed").exists()


def test_top_level_names_match():
    names = set()
    for node in stub_tree().body:
        if isinstance(node, (ast.FunctionDef, ast.ClassDef)):
            names.add(node.name)
        elif isinstance(node, ast.AnnAssign):
            names.add(node.target.id)
    names = {n for n in names if not n.startswith("_") or n == "__version__"}
    assert names == set(cover.__all__)
    assert all(hasattr(cover, n) for n in cover.__all__)


def test_model_members_and_parameters_match():
    model_stub = next(n for n in stub_tree().body if isinstance(n, ast.ClassDef) and n.name == "Model")
    stub_members = {n.name: n for n in model_stub.body if isinstance(n, ast.FunctionDef)}
    runtime = {n for n in dir(cover.Model) if not n.startswith("_")}
    runtime |= {"__init__", "__or__", "__and__", "__sub__", "__invert__"}
    assert set(stub_members) == runtime
    for name, fn in stub_members.items():
        member = getattr(cover.Model, name)
        if isinstance(member, property):
            assert member.__doc__, name
            continue
        if name.startswith("__"):
            continue
        assert params(fn) == runtime_params(member), name


def test_function_parameters_match():
    for node in stub_tree().body:
        if isinstance(node, ast.FunctionDef):
            assert params(node) == runtime_params(getattr(cover, node.name)), node.name


def test_every_function_has_a_docstring():
    for name in cover.__all__:
        obj = getattr(cover, name)
        if isinstance(obj, type):
            assert obj.__doc__, name
        elif callable(obj):  # a pybind11 signature line, a blank line, then the text
            assert obj.__doc__ and len(obj.__doc__.splitlines()) > 2, name
    for name in dir(cover.Model):
        if not name.startswith("_") or name in ("__or__", "__and__", "__sub__", "__invert__"):
            assert getattr(cover.Model, name).__doc__, name


def test_names_table_matches_the_stubs_and_the_cpp_docs():
    """docs/python.md "Names: Python and C++" lists exactly the public names of the stubs, and
    each C++ name it pairs them with is in docs/library.md (the C++ facade's reference)."""
    docs = pathlib.Path(__file__).parents[2] / "docs"
    text = (docs / "python.md").read_text(encoding="utf-8")
    section = text[text.index("## Names: Python and C++"):]
    section = section[:section.index("\n## ", 1)]
    rows = re.findall(r"^\| `([^`]+)` \| (?:`([^`]+)`|—) \|$", section, flags=re.M)
    assert len(rows) > 40
    listed = {py for py, _ in rows}
    model_stub = next(n for n in stub_tree().body if isinstance(n, ast.ClassDef) and n.name == "Model")
    members = {n.name for n in model_stub.body if isinstance(n, ast.FunctionDef)}
    members = {n for n in members if not n.startswith("_")}
    expected = {f"cover.{n}" for n in cover.__all__} | {f"Model.{n}" for n in members}
    assert listed == expected
    library = (docs / "library.md").read_text(encoding="utf-8")
    missing = [cpp for _, cpp in rows if cpp and cpp not in library]
    assert not missing
