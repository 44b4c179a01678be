"""The package itself: its stubs and docstrings, and the example script."""

import inspect
import pathlib
import subprocess
import sys

import pytest

import drape

PACKAGE = pathlib.Path(drape.__file__).parent
EXAMPLE = pathlib.Path(__file__).resolve().parents[1] / "examples" / "energy_and_corner.py"


def public_members():
    for name in drape.__all__:
        if name.startswith("__"):
            continue
        item = getattr(drape, name)
        yield name, item
        if inspect.isclass(item) and not issubclass(item, BaseException):
            for member, value in vars(item).items():
                if not member.startswith("_") or member == "__init__":
                    yield f"{name}.{member}", value


def test_every_class_function_and_member_has_a_docstring():
    missing = [name for name, item in public_members() if not (getattr(item, "__doc__", None) or "").strip()]
    assert not missing, missing


def test_the_stubs_cover_the_package():
    stub = (PACKAGE / "_drape.pyi").read_text()
    assert (PACKAGE / "py.typed").exists()
    for name in drape.__all__:
        if name.startswith("__") or name in ("InvalidParameter",):
            continue
        assert f"class {name}" in stub or f"def {name}(" in stub or f"{name}:" in stub, name
    # Signatures carry the keyword arguments and their types.
    assert "def run(self, state: State, seconds: float" in stub
    assert "nx: int | None = None" in stub


def test_example_script_writes_its_plot(tmp_path):
    pytest.importorskip("matplotlib")
    out = tmp_path / "plot.png"
    subprocess.run([sys.executable, str(EXAMPLE), "--seconds", "0.3", "--out", str(out)], check=True)
    assert out.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
