"""The type stubs shipped with the package (brdfbake/_core.pyi, py.typed) describe what the extension
holds: every class, method, property and function, no more, no less."""

import ast
import inspect
import pathlib
import re

import brdfbake
from brdfbake import _core


def stub_tree():
    path = pathlib.Path(_core.__file__).with_name("_core.pyi")
    assert path.exists() and path.with_name("py.typed").exists()
    return ast.parse(path.read_text())


def public(names):
    return {n for n in names if not n.startswith("__")}


def test_the_stub_lists_every_class_member_and_function():
    tree = stub_tree()
    classes = {node.name: node for node in tree.body if isinstance(node, ast.ClassDef)}
    functions = {node.name for node in tree.body if isinstance(node, ast.FunctionDef)}
    runtime_classes = {n for n, v in vars(_core).items() if inspect.isclass(v)}
    runtime_functions = {n for n, v in vars(_core).items() if callable(v) and not inspect.isclass(v)}
    assert set(classes) == runtime_classes
    assert functions == public(runtime_functions)
    for name, node in classes.items():
        stubbed = {item.name for item in node.body if isinstance(item, ast.FunctionDef)}
        assert public(stubbed) == public(dir(getattr(_core, name))) - {"_pybind11_conduit_v1_"}, name


def test_the_stub_functions_take_the_extensions_arguments_in_order():
    # pybind11's signature line, "name(a: T, b: U = ...) -> R": the names before each ": ".
    for node in stub_tree().body:
        if isinstance(node, ast.FunctionDef) and not node.name.startswith("__"):
            line = getattr(_core, node.name).__doc__.splitlines()[0]
            runtime = re.findall(r"(\w+): ", line[line.index("(") + 1:line.rindex(") ->")])
            assert [a.arg for a in node.args.args + node.args.kwonlyargs] == runtime, node.name


def test_the_package_exports_what_it_documents():
    for name in brdfbake.__all__:
        assert hasattr(brdfbake, name), name
    for function in (brdfbake.bake, brdfbake.fit, brdfbake.prefilter, brdfbake.read_map):
        assert function.__doc__ and len(function.__doc__) > 200
    assert brdfbake.__version__ == _core.version
    assert isinstance(brdfbake.Map.sample.__doc__, str) and "brdfbake sample" in brdfbake.Map.sample.__doc__
