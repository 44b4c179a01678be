"""Shared fixtures: the repository's scenes and drape-render, the C++ reference program."""

import os
import pathlib
import shutil

import pytest

REPO = pathlib.Path(__file__).resolve().parents[2]
SCENES = REPO / "scenes"


def find_drape_render():
    """drape-render from $DRAPE_RENDER, else a build folder of this checkout, else PATH."""
    given = os.environ.get("DRAPE_RENDER")
    if given:
        return pathlib.Path(given)
    for folder in ("py-ref", "release"):
        candidate = REPO / "build" / folder / "viewer" / "drape-render"
        if candidate.exists():
            return candidate
    found = shutil.which("drape-render")
    return pathlib.Path(found) if found else None


@pytest.fixture(scope="session")
def drape_render():
    """The C++ program the bit-identity tests compare against (scripts/python.sh builds it).
    Missing: skipped, or failed when DRAPE_REQUIRE_REFERENCE=1."""
    path = find_drape_render()
    if path is None or not path.exists():
        message = "drape-render not found (set DRAPE_RENDER; scripts/python.sh builds it)"
        if os.environ.get("DRAPE_REQUIRE_REFERENCE") == "1":
            pytest.fail(message)
        pytest.skip(message)
    return path


@pytest.fixture(scope="session")
def scenes():
    return SCENES
