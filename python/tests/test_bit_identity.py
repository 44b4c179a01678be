"""The Python step against the C++ program: drape-render, built separately with the same compiler,
runs the same scene with the same thread count; its state file (17 digits, read back bit for bit)
and OBJ meshes must equal the Python state's bits, and its state file must equal Python's byte for byte."""

import subprocess

import numpy as np
import pytest

import drape


def bits(array):
    return np.ascontiguousarray(array, dtype=np.float64).view(np.uint64)


def assert_same_bits(python_state, reference_state):
    assert python_state.time == reference_state.time
    assert np.array_equal(bits(python_state.positions), bits(reference_state.positions))
    assert np.array_equal(bits(python_state.velocities), bits(reference_state.velocities))


def render(drape_render, tmp_path, *flags):
    out = tmp_path / "frames"
    subprocess.run([str(drape_render), "--quiet", "--no-csv", "--width", "32", "--height", "24", "--out", str(out),
                    *flags], check=True)
    return out


@pytest.mark.parametrize("threads", [1, 2])
def test_default_scene_rk2(drape_render, tmp_path, threads):
    """The library's default cloth and RK2, stepped with the low-level API."""
    reference = tmp_path / "reference.state"
    render(drape_render, tmp_path, "--frames", "4", "--frame-time", "0.05", "--threads", str(threads),
           "--save-state", str(reference))
    cloth = drape.Cloth(drape.ClothSpec())
    rk2 = drape.Rk2(cloth, threads=threads)
    state = cloth.initial_state()
    for _ in range(300):  # 3 frames of 0.05 s at dt = 5e-4, one step() at a time
        rk2.step(state)
    assert_same_bits(state, drape.load_state(str(reference)))
    mine = tmp_path / "python.state"
    drape.save_state(str(mine), state)
    assert mine.read_bytes() == reference.read_bytes()


@pytest.mark.parametrize("scene_name, integrator", [
    ("curtain.toml", "implicit"),        # moving pins ([[moving-pins]]), released mid-way
    ("flag.toml", "implicit"),           # wind, gusts, aerodynamic force
    ("drop_on_sphere.toml", "implicit"),  # colliders with friction, the floor collider
    ("one_corner.toml", "symplectic"),
])
def test_scene_files(drape_render, tmp_path, scenes, scene_name, integrator):
    """A scene file read by load_scene() and run by ClothScene.run() against drape-render on the file."""
    reference = tmp_path / "reference.state"
    flags = ["--threads", "2", "--frames", "16", "--integrator", integrator]
    if integrator == "symplectic":
        flags += ["--dt", "0.0002"]
    render(drape_render, tmp_path, "--scene", str(scenes / scene_name), *flags, "--save-state", str(reference))
    scene_file = drape.load_scene(str(scenes / scene_name), flags)
    scene = scene_file.make_scene()
    scene.run(scene_file.seconds, frame_time=scene_file.frame_time)
    assert_same_bits(scene.state(0), drape.load_state(str(reference)))


def read_obj_vertices(path):
    return np.array([[float(v) for v in line.split()[1:]] for line in path.read_text().splitlines()
                     if line.startswith("v ")])


def test_two_cloths_self_collision(drape_render, tmp_path, scenes):
    """Two cloths colliding with each other ([[cloths]]): drape-render writes both in one OBJ per frame."""
    flags = ["--threads", "2", "--frames", "10"]
    out = render(drape_render, tmp_path, "--scene", str(scenes / "two_cloths_over_box.toml"), *flags, "--obj")
    scene_file = drape.load_scene(str(scenes / "two_cloths_over_box.toml"), flags)
    assert len(scene_file.cloth_specs) == 2
    scene = scene_file.make_scene()
    scene.run(scene_file.seconds)
    positions = np.vstack([s.positions for s in scene.states])
    reference = read_obj_vertices(out / f"frame_{scene_file.frame_count - 1:05d}.obj")
    assert reference.shape == positions.shape
    assert np.array_equal(bits(positions), bits(reference))
