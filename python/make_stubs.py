"""Writes dynid.pyi, the type stubs of the built `dynid` module, at build time.

Usage: python3 make_stubs.py MODULE_DIR OUT.pyi

mypy's stubgen reads the signatures pybind11 gives every function (the argument types come from
python/common.hpp's Typed<Tag> names); this script then spells pybind11's array types the way
type checkers read them (every array dynid returns is float64) and types stubgen's untyped
constructors. tests/python/test_stubs.py checks the result with mypy --strict.
"""

import os
import re
import sys
import tempfile


def generate(module_dir: str) -> str:
    sys.path.insert(0, module_dir)
    from mypy.stubgen import main as stubgen  # Debian's python3-mypy

    with tempfile.TemporaryDirectory() as out:
        argv = sys.argv
        sys.argv = ["stubgen", "-q", "-m", "dynid", "-o", out]
        try:
            stubgen()
        finally:
            sys.argv = argv
        with open(os.path.join(out, "dynid.pyi"), encoding="utf-8") as f:
            return f.read()


def fix(text: str) -> str:
    array = "numpy.typing.NDArray[numpy.float64]"
    text = text.replace("numpy.ndarray[numpy.float64]", array)
    text = re.sub(r"numpy\.ndarray(?!\[)", array, text)
    text = text.replace("(self, *args, **kwargs)", "(self, *args: Any, **kwargs: Any)")
    # A function that forwards to pure Python (summarize_many): its arguments as they come.
    text = text.replace("(*args, **kwargs) -> object", "(*args: Any, **kwargs: Any) -> Any")
    # Bare containers (pybind11's py::dict and py::list): keys are names, values vary.
    text = re.sub(r"(?<![\w.])dict(?![\w\[])", "dict[str, Any]", text)
    text = re.sub(r"(?<![\w.])list(?![\w\[])", "list[Any]", text)
    header = "# Generated from the built module by python/make_stubs.py; do not edit.\n"
    return header + text


def main() -> int:
    if len(sys.argv) != 3:
        print(__doc__, file=sys.stderr)
        return 2
    text = fix(generate(sys.argv[1]))
    out = sys.argv[2]
    fd, tmp = tempfile.mkstemp(dir=os.path.dirname(os.path.abspath(out)), prefix=".dynid.pyi.")
    with os.fdopen(fd, "w", encoding="utf-8") as f:
        f.write(text)
    os.chmod(tmp, 0o644)  # an installed file, read by every user
    os.replace(tmp, out)
    return 0


if __name__ == "__main__":
    sys.exit(main())
