"""drape-render's USD file (--usd) read with Pixar's USD library (the PyPI package usd-core): the
cloth's points at every time code are the OBJ frames' in single precision, its faces theirs, and
every collider is a mesh moving with its pose."""

import subprocess

import numpy as np
import pytest

Usd = pytest.importorskip("pxr.Usd", reason="usd-core is not installed (pip install usd-core)")
from pxr import UsdGeom  # noqa: E402  (after the skip)

FRAMES = 5
FRAME_TIME = 0.05

# A small free cloth falling onto a sphere that moves along x, and the floor collider.
SCENE = f"""
integrator = "implicit"
dt = 0.025
nx = 9
ny = 7
spacing = 0.1
pins = []
floor-collider = true
floor-height = -0.6
frames = {FRAMES}
frame-time = {FRAME_TIME}

[[colliders]]
shape = "sphere"
center = [0.4, -0.2, 0.3]
radius = 0.15
velocity = [0.5, 0.0, 0.0]
"""


def read_obj(path):
    """The vertices (n x 3) and triangles (0-based, m x 3) of an OBJ file drape-render wrote."""
    vertices, faces = [], []
    for line in path.read_text().splitlines():
        if line.startswith("v "):
            vertices.append([float(x) for x in line.split()[1:4]])
        elif line.startswith("f "):
            faces.append([int(x) - 1 for x in line.split()[1:4]])
    return np.array(vertices), np.array(faces)


def test_usd_file_holds_the_obj_frames_and_the_moving_colliders(drape_render, tmp_path):
    scene = tmp_path / "scene.toml"
    scene.write_text(SCENE)
    out = tmp_path / "frames"
    usd_path = out / "scene.usda"  # in the --out folder, which drape-render creates
    subprocess.run([str(drape_render), "--quiet", "--no-csv", "--width", "64", "--height", "48", "--scene",
                    str(scene), "--out", str(out), "--obj", "--usd", str(usd_path)], check=True)

    stage = Usd.Stage.Open(str(usd_path))
    assert UsdGeom.GetStageUpAxis(stage) == UsdGeom.Tokens.y
    assert UsdGeom.GetStageMetersPerUnit(stage) == 1
    assert stage.GetTimeCodesPerSecond() == pytest.approx(1 / FRAME_TIME)
    assert (stage.GetStartTimeCode(), stage.GetEndTimeCode()) == (0, FRAMES - 1)
    root = stage.GetDefaultPrim()
    assert root.GetName() == "drape" and root.IsA(UsdGeom.Xform)
    meshes = {prim.GetName(): UsdGeom.Mesh(prim) for prim in root.GetChildren()}
    assert sorted(meshes) == ["cloth", "plane", "sphere"]

    cloth = meshes["cloth"]
    assert cloth.GetSubdivisionSchemeAttr().Get() == UsdGeom.Tokens.none
    _, triangles = read_obj(out / "frame_00000.obj")
    assert list(cloth.GetFaceVertexCountsAttr().Get()) == [3] * len(triangles)
    assert np.array_equal(np.array(cloth.GetFaceVertexIndicesAttr().Get()).reshape(-1, 3), triangles)
    assert cloth.GetPointsAttr().GetTimeSamples() == list(range(FRAMES))
    for frame in range(FRAMES):
        vertices, _ = read_obj(out / f"frame_{frame:05d}.obj")
        points = np.array(cloth.GetPointsAttr().Get(frame), dtype=np.float32)
        # USD's point3f is a float: the OBJ's full-precision values rounded to single precision.
        assert np.array_equal(points, vertices.astype(np.float32)), frame
        extent = np.array(cloth.GetExtentAttr().Get(frame))
        assert np.array_equal(extent, [points.min(axis=0), points.max(axis=0)]), frame
    assert not np.array_equal(cloth.GetPointsAttr().Get(0), cloth.GetPointsAttr().Get(FRAMES - 1))  # it falls

    # The sphere: its points on its surface at every frame, its centre moving at 0.5 m/s along x.
    sphere = meshes["sphere"]
    for frame in range(FRAMES):
        points = np.array(sphere.GetPointsAttr().Get(frame), dtype=np.float64)
        centre = np.array([0.4 + 0.5 * FRAME_TIME * frame, -0.2, 0.3])
        assert np.allclose(np.linalg.norm(points - centre, axis=1), 0.15, atol=1e-6), frame
    faces = np.array(sphere.GetFaceVertexIndicesAttr().Get()).reshape(-1, 3)
    assert len(np.unique(faces)) == len(sphere.GetPointsAttr().Get(0))  # every point on a face
    # A closed surface: every edge in two triangles, once each way.
    edges = {(a, b) for f in faces for a, b in ((f[0], f[1]), (f[1], f[2]), (f[2], f[0]))}
    assert len(edges) == 3 * len(faces) and all((b, a) in edges for a, b in edges)

    # The floor: a square at its height.
    floor = np.array(meshes["plane"].GetPointsAttr().Get(0))
    assert floor.shape == (4, 3) and np.allclose(floor[:, 1], -0.6)


def test_usd_path_is_checked_before_the_run(drape_render, tmp_path):
    for usd, expected in ((tmp_path / "scene.usd", "--usd (extension)"),
                          (tmp_path / "missing" / "scene.usda", "existing folder")):
        run = subprocess.run([str(drape_render), "--quiet", "--frames", "1", "--out", str(tmp_path / "frames"),
                              "--usd", str(usd)], capture_output=True, text=True)
        assert run.returncode == 2 and expected in run.stderr, run.stderr
        assert not (tmp_path / "frames").exists()
