"""The type stub generated at build time (pysph_bindings/generate_stubs.py): it sits beside the
module, parses, declares every public class, function, method and property of consph._consph, and
carries pybind11's signatures rather than `object`."""
import ast
import inspect
import os

import consph
import consph._consph as native


def _stub():
    path = os.path.join(os.path.dirname(native.__file__), "_consph.pyi")
    return ast.parse(open(path).read())


def test_stub_declares_everything_the_module_has():
    tree = _stub()
    classes = {node.name: node for node in tree.body if isinstance(node, ast.ClassDef)}
    functions = {node.name for node in tree.body if isinstance(node, ast.FunctionDef)}
    for name, value in vars(native).items():
        if name.startswith("__"):
            continue
        if inspect.isclass(value):
            assert name in classes, name
            declared = {n.name for n in classes[name].body if isinstance(n, ast.FunctionDef)}
            for member, attr in vars(value).items():
                if not member.startswith("_") and (isinstance(attr, (property, staticmethod)) or callable(attr)):
                    assert member in declared, f"{name}.{member}"
        elif callable(value):
            assert name in functions, name


def test_stub_has_real_signatures():
    tree = _stub()
    simulation = next(n for n in tree.body if isinstance(n, ast.ClassDef) and n.name == "Simulation")
    methods = {n.name: n for n in simulation.body if isinstance(n, ast.FunctionDef)}
    step = methods["step"]
    assert [a.arg for a in step.args.args] == ["self", "n"] and ast.unparse(step.args.args[1].annotation) == "int"
    assert ast.unparse(step.args.defaults[0]) == "1" and ast.unparse(step.returns) == "None"
    from_file = methods["from_file"]
    assert [ast.unparse(d) for d in from_file.decorator_list] == ["staticmethod"]
    assert "restart" in [a.arg for a in from_file.args.kwonlyargs]
    assert ast.unparse(from_file.returns) == "Simulation"
    time = next(n for n in simulation.body if isinstance(n, ast.FunctionDef) and n.name == "time")
    assert ast.unparse(time.returns) == "float" and ast.get_docstring(time) == "simulated time, s"
    assert os.path.exists(os.path.join(os.path.dirname(consph.__file__), "py.typed"))
