"""The type stubs list exactly what the module exports, with the same keyword arguments."""
import ast
import inspect
import pathlib
import re

import loopscan
from loopscan import _loopscan

STUB = pathlib.Path(loopscan.__file__).with_name("_loopscan.pyi")


def stub_tree():
    return ast.parse(STUB.read_text())


def test_every_public_name_is_stubbed_and_nothing_else():
    tree = stub_tree()
    stubbed = {n.name for n in tree.body if isinstance(n, (ast.FunctionDef, ast.ClassDef))}
    stubbed |= {n.target.id for n in tree.body if isinstance(n, ast.AnnAssign)}
    public = {n for n in dir(_loopscan) if not n.startswith("_")} | {"__version__"}
    assert stubbed - {"Array", "IntArray", "Poses", "Points"} == public


def test_function_keywords_match_the_module():
    for node in stub_tree().body:
        if not isinstance(node, ast.FunctionDef):
            continue
        doc = getattr(_loopscan, node.name).__doc__
        # pybind11 puts the signature first: name(arg: type = default, ...) -> ...
        names = re.findall(r"(\w+): ", doc.split("->")[0])
        assert [a.arg for a in node.args.args] == names, node.name
    # Methods too: constructor and query keywords are the ones users type most.
    for cls, method in [("Database", "query"), ("Database", "add"), ("Recognizer", "__init__"),
                        ("StereoVo", "__init__"), ("LoopCloser", "add_keyframe")]:
        doc = getattr(getattr(_loopscan, cls), method).__doc__
        names = [n for n in re.findall(r"(\w+): ", doc.split("->")[0]) if n != "self"]
        stub_cls = next(n for n in stub_tree().body if isinstance(n, ast.ClassDef) and n.name == cls)
        stub_fn = next(n for n in stub_cls.body if isinstance(n, ast.FunctionDef) and n.name == method)
        assert [a.arg for a in stub_fn.args.args[1:]] == names, (cls, method)
    assert inspect.isclass(loopscan.Database)
