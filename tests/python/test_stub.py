"""The type stub hemivem/__init__.pyi names exactly what the module offers."""

import ast
import inspect
import pathlib

import hemivem


def stub_tree():
    return ast.parse((pathlib.Path(hemivem.__file__).parent / "__init__.pyi").read_text())


def public(names):
    return {n for n in names if not n.startswith("_")}


def test_stub_names_every_public_name_and_member():
    tree = stub_tree()
    top = {node.name for node in tree.body if isinstance(node, (ast.ClassDef, ast.FunctionDef))}
    assert top == set(hemivem.__all__)
    for node in tree.body:
        if not isinstance(node, ast.ClassDef):
            continue
        cls = getattr(hemivem, node.name)
        stub_members = set()
        for item in node.body:
            if isinstance(item, ast.FunctionDef):
                stub_members.add(item.name)
            elif isinstance(item, ast.AnnAssign):
                stub_members.add(item.target.id)
        if issubclass(cls, BaseException):
            assert stub_members <= {"where", "detail", "element"}
            continue
        runtime = public(name for name, _ in inspect.getmembers(cls))
        assert public(stub_members) == runtime, node.name


def test_docstrings_and_signatures():
    for name in hemivem.__all__:
        obj = getattr(hemivem, name)
        assert obj.__doc__, name
    assert "linear" in hemivem.solve.__doc__ and "keep_reduced" in hemivem.solve.__doc__
    assert "tolerance" in hemivem.minimize.__doc__
