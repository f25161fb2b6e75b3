"""Writes PACKAGE/_consph.pyi, the type stub of the compiled module, so that IDEs, type checkers
and help() on the stub show real signatures instead of `object`. Run at build time (CMake, after
linking _consph) as: python3 generate_stubs.py BUILD/python/consph.

pybind11 puts each function's signature on the first line of its docstring
("step(self: consph._consph.Simulation, n: int = 1) -> None"; overloads as "1. ...", "2. ...");
this script turns those lines into stub declarations, keeps the rest of each docstring, and
checks that the result parses. pybind11-stubgen does the same but is not a Debian package.
"""
import ast
import importlib
import inspect
import os
import re
import sys

_QUALIFIED = re.compile(r"\bconsph\._consph\.")
_NDARRAY = re.compile(r"numpy\.ndarray\[[^\]]*\](\[[^\]]*\])*")
_BAD_DEFAULT = re.compile(r"=\s*<[^>]*>")  # reprs such as <object object at 0x...> are no Python
_CPP_TYPE = re.compile(r"[A-Za-z_][\w]*(::[\w<>, ]+)+")  # a C++ type pybind11 has no Python name for


def _clean(signature):
    signature = _QUALIFIED.sub("", signature)
    signature = _NDARRAY.sub("numpy.ndarray", signature)
    signature = _CPP_TYPE.sub("typing.Any", signature)
    return _BAD_DEFAULT.sub("= ...", signature)


def _signatures(name, doc):
    """[(parameters, return type)] from a pybind11 docstring; several for an overloaded function."""
    lines = (doc or "").splitlines()
    pattern = re.compile(r"^(?:\d+\. )?" + re.escape(name) + r"(\(.*\))\s*->\s*(.+)$")
    found = [pattern.match(line.strip()) for line in lines]
    return [(_clean(m.group(1)), _clean(m.group(2))) for m in found if m]


def _body(doc, indent):
    """The docstring without its signature lines, as a stub body."""
    text = "\n".join(line for line in (doc or "").splitlines()
                     if not re.match(r"^(\d+\. )?\w+\(.*\)\s*->", line.strip()) and line.strip() != "Overloaded function.")
    text = text.strip().replace("\\", "\\\\").replace('"""', '\\"\\"\\"')
    return f'{indent}    """{text}"""\n' if text else f"{indent}    ...\n"


def _function(name, doc, indent, decorator=None):
    out = []
    sigs = _signatures(name, doc)
    if not sigs:
        sigs = [("(self, *args, **kwargs)" if indent else "(*args, **kwargs)", "typing.Any")]
    for params, returns in sigs:
        if len(sigs) > 1:
            out.append(f"{indent}@typing.overload\n")
        if decorator:
            out.append(f"{indent}@{decorator}\n")
        # pybind11 names the instance `self` in methods but `arg0` in property getters.
        params = re.sub(r"^\(arg0: \w+", "(self", params) if indent else params
        params = re.sub(r"^\(self: \w+", "(self", params)
        out.append(f"{indent}def {name}{params} -> {returns}:\n{_body(doc, indent)}")
    return "".join(out)


def _property(name, prop, indent):
    sig = _signatures("", prop.fget.__doc__ if prop.fget else "")
    returns = sig[0][1] if sig else "typing.Any"
    out = f"{indent}@property\n{indent}def {name}(self) -> {returns}:\n{_body(prop.__doc__, indent)}"
    if prop.fset is not None:
        out += f"{indent}@{name}.setter\n{indent}def {name}(self, value: {returns}) -> None: ...\n"
    return out


def _class(name, cls):
    bases = [b.__name__ for b in cls.__bases__ if b is not object and b.__name__ != "pybind11_object"]
    out = [f"class {name}({', '.join(bases)}):\n" if bases else f"class {name}:\n"]
    if cls.__doc__ and not issubclass(cls, BaseException):
        out.append(_body(cls.__doc__, ""))
    members = 0
    for key, value in cls.__dict__.items():
        if key.startswith("_") and key not in ("__init__", "__len__", "__repr__", "__getitem__"):
            continue
        if isinstance(value, property):
            out.append(_property(key, value, "    "))
        elif isinstance(value, staticmethod):
            out.append(_function(key, value.__func__.__doc__, "    ", "staticmethod"))
        elif callable(value):
            if key.startswith("_") and not _signatures(key, value.__doc__):
                continue  # object's slot wrappers (a class without a constructor), not consph's
            out.append(_function(key, value.__doc__, "    "))
        else:
            continue
        members += 1
    if members == 0 and len(out) == 1:
        out.append("    ...\n")
    return "".join(out)


def generate(module):
    parts = ['"""Type stub of consph._consph (generated at build time by pysph_bindings/generate_stubs.py)."""\n',
             "import typing\n\nimport numpy\n\n"]
    for name, value in sorted(vars(module).items()):
        if name.startswith("__") and name != "__version__":
            continue
        if inspect.isclass(value):
            parts.append(_class(name, value) + "\n")
        elif callable(value):
            parts.append(_function(name, value.__doc__, "") + "\n")
        elif isinstance(value, (str, int, float)):
            parts.append(f"{name}: {type(value).__name__}\n")
    return "".join(parts)


def main(package_dir):
    sys.path.insert(0, os.path.dirname(os.path.abspath(package_dir)))
    module = importlib.import_module("consph._consph")
    stub = generate(module)
    ast.parse(stub)  # a stub that does not parse is a build error, not a silent IDE failure
    path = os.path.join(package_dir, "_consph.pyi")
    with open(path + ".tmp", "w") as f:
        f.write(stub)
    os.replace(path + ".tmp", path)
    with open(os.path.join(package_dir, "py.typed"), "w"):
        pass  # PEP 561: the package ships its types


if __name__ == "__main__":
    main(sys.argv[1])
