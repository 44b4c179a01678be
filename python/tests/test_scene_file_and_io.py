"""Scene files, OBJ and state files, rendering."""

import os

import numpy as np
import pytest

import drape


@pytest.mark.parametrize("name", sorted(p.name for p in __import__("conftest").SCENES.glob("*.toml")))
def test_every_scene_of_the_repository_loads(scenes, name):
    scene_file = drape.load_scene(str(scenes / name))
    assert scene_file.integrator in drape.option_names()["integrator"]
    assert scene_file.frame_count >= 1 and scene_file.cloth_specs
    scene = scene_file.make_scene()
    assert scene.state(0).node_count == drape.Cloth(scene_file.cloth_specs[0]).node_count


def test_scene_file_contents_and_flags(scenes):
    flag = drape.load_scene(str(scenes / "flag.toml"), ["--threads", "1", "--dt", "0.01"])
    assert flag.options.threads == 1 and flag.options.dt == 0.01 and flag.integrator == "implicit"
    spec = flag.cloth_specs[0]
    assert spec.air.active and spec.air.wind[0] > 0
    assert drape.Cloth(spec).force_terms  # the air becomes force terms, as in drape-render
    assert flag.path.endswith("flag.toml")


def test_scene_file_errors_name_the_key(tmp_path):
    bad = tmp_path / "bad.toml"
    bad.write_text("frame_time = 0.1\n")
    with pytest.raises(drape.SceneFileError, match="unknown key 'frame_time' \\(did you mean 'frame-time'\\?\\)"):
        drape.load_scene(str(bad))
    bad.write_text("shear-kd = -1.0\n")
    with pytest.raises(ValueError, match="--shear-kd = -1 is invalid"):
        drape.load_scene(str(bad))
    bad.write_text("[[colliders]]\nshape = 'sphere'\ncenter = [1, -1, 1]\nradius = -2\n")
    with pytest.raises(drape.SceneFileError, match="colliders\\[0\\].radius = -2"):
        drape.load_scene(str(bad))
    with pytest.raises(drape.SceneFileError, match="missing.toml.*could not be opened"):
        drape.load_scene(str(tmp_path / "missing.toml"))


def test_scene_file_load_state(tmp_path, scenes):
    cloth = drape.Cloth(drape.ClothSpec(boundary="one-corner"))
    state = cloth.initial_state()
    drape.Rk2(cloth, threads=1).run(state, 0.05)
    saved = tmp_path / "saved.state"
    drape.save_state(str(saved), state)
    scene_file = drape.load_scene(str(scenes / "one_corner.toml"), ["--load-state", str(saved)])
    assert scene_file.start.time == state.time
    assert np.array_equal(scene_file.make_scene().state(0).positions, state.positions)


def test_obj_and_state_files(tmp_path):
    cloth = drape.Cloth(drape.ClothSpec(nx=5, ny=4))
    state = cloth.initial_state()
    drape.Rk2(cloth, threads=1).run(state, 0.02)
    obj = tmp_path / "cloth.obj"
    drape.write_obj(str(obj), state.positions, cloth.triangles)
    lines = obj.read_text().splitlines()
    vertices = np.array([[float(v) for v in l.split()[1:]] for l in lines if l.startswith("v ")])
    faces = np.array([[int(v) for v in l.split()[1:]] for l in lines if l.startswith("f ")])
    assert np.array_equal(vertices, state.positions)  # 17 digits: the same bits
    assert np.array_equal(faces - 1, cloth.triangles)
    path = tmp_path / "cloth.state"
    drape.save_state(str(path), state)
    loaded = drape.load_state(str(path), expected_nodes=20)
    assert loaded.time == state.time and np.array_equal(loaded.velocities, state.velocities)
    assert not any(p.name.endswith(".tmp") for p in tmp_path.iterdir())  # atomic writes leave nothing behind
    with pytest.raises(drape.StateFormatError, match="nodes"):
        drape.load_state(str(path), expected_nodes=21)
    (tmp_path / "garbage.state").write_text("not a state\n")
    with pytest.raises(drape.StateFormatError, match="garbage.state"):
        drape.load_state(str(tmp_path / "garbage.state"))
    with pytest.raises(drape.FileWriteError, match="no-such-folder") as error:
        drape.save_state(str(tmp_path / "no-such-folder" / "x.state"), state)
    assert isinstance(error.value, OSError)


def test_render_a_png(tmp_path):
    cloth = drape.Cloth(drape.ClothSpec(nx=17, ny=17, colliders=[drape.Collider.sphere((0.8, -1.0, 0.8), 0.4)]))
    state = cloth.initial_state()
    drape.Rk2(cloth, threads=1).run(state, 0.2)
    renderer = drape.Renderer(cloth, state, width=160, height=120, camera="fixed")
    png = tmp_path / "frame.png"
    image = renderer.render(str(png))
    assert image.shape == (120, 160, 3) and image.dtype == np.uint8
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    red = (image[..., 0] > 150) & (image[..., 1] < 120)  # the cloth's upper side
    assert red.sum() > 100
    assert renderer.render().shape == image.shape  # renders again
    with pytest.raises(ValueError, match="'camera' = 'orbit'"):
        drape.Renderer(cloth, state, camera="orbit")
    with pytest.raises(drape.FileWriteError):
        renderer.render(str(tmp_path / "missing" / "frame.png"))


def test_render_matches_drape_render(drape_render, tmp_path, scenes):
    """The scene file's renderer draws the first frame exactly as drape-render does (same PNG bytes)."""
    import subprocess

    for name in ("two_corners.toml", "tablecloth.toml"):
        flags = ["--width", "160", "--height", "120", "--frames", "1"]
        out = tmp_path / name
        subprocess.run([str(drape_render), "--quiet", "--no-csv", "--scene", str(scenes / name), *flags,
                        "--out", str(out)], check=True)
        scene_file = drape.load_scene(str(scenes / name), flags)
        scene = scene_file.make_scene()
        png = tmp_path / f"{name}.png"
        scene_file.renderer(scene).render(str(png))
        assert png.read_bytes() == (out / "frame_00000.png").read_bytes(), name
