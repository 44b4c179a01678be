"""The core: specs, cloths, states shared with numpy, integrators, pins, scenes."""

import gc
import threading
import time

import numpy as np
import pytest

import drape


def data_pointer(array):
    return array.__array_interface__["data"][0]


def small_cloth(**overrides):
    return drape.Cloth(drape.ClothSpec(nx=9, ny=9, **overrides))


def test_spec_keywords_and_defaults():
    spec = drape.ClothSpec(boundary="one-corner", shear=(4000, 4), bend=drape.SpringParams(300, 2))
    assert (spec.nx, spec.ny, spec.spacing, spec.node_mass, spec.gravity) == (33, 33, 0.1, 0.03, 10.0)
    assert spec.boundary == "one-corner"
    assert (spec.springs.shear.stiffness, spec.springs.shear.damping) == (4000, 4)
    assert spec.springs.structural.stiffness == 20000  # the default
    spec.springs.bend.stiffness = 250  # edits in place
    assert spec.springs.bend.stiffness == 250
    cloth = drape.Cloth(spec)
    assert cloth.node_count == 33 * 33 and cloth.pinned_nodes == [0]
    assert cloth.triangles.shape == (2 * 32 * 32, 3) and cloth.triangles.dtype == np.int32
    assert cloth.node(32, 0) == 32


def test_positions_and_velocities_are_views_of_the_state():
    cloth = small_cloth()
    rk2 = drape.Rk2(cloth, threads=1)
    state = cloth.initial_state()
    x, v = state.positions, state.velocities
    assert x.shape == (81, 3) and x.dtype == np.float64 and x.flags["C_CONTIGUOUS"] and x.flags["WRITEABLE"]
    pointer = data_pointer(x)
    for _ in range(5):
        rk2.step(state)
    # The arrays taken before the steps see the new state: one buffer for the state's life.
    assert data_pointer(state.positions) == pointer and np.shares_memory(x, state.positions)
    assert x[80, 1] < 0 and np.array_equal(v, state.velocities) and v[80, 1] < 0
    rk2.run(state, 0.01)
    assert data_pointer(state.positions) == pointer and x[80, 1] == state.positions[80, 1]


def test_writing_into_the_arrays_changes_the_cpp_state():
    cloth = small_cloth()
    state = cloth.initial_state()
    assert cloth.spring_energy(state) < 1e-20
    state.positions[40, 1] += 0.01  # C++ sees the write: the springs stretch
    assert cloth.spring_energy(state) > 1e-3
    state.velocities[:, 0] = 1.0
    assert cloth.kinetic_energy(state) == pytest.approx(0.5 * 81 * 0.03)
    # A step starts from the written values: the same as a state built from copies of them.
    copy = drape.State(state.positions.copy(), state.velocities.copy())
    a, b = drape.Rk2(cloth, threads=1), drape.Rk2(cloth, threads=1)
    a.step(state)
    b.step(copy)
    assert np.array_equal(state.positions, copy.positions) and np.array_equal(state.velocities, copy.velocities)
    # Assigning an array copies into the same buffer.
    pointer = data_pointer(state.positions)
    state.positions = np.zeros((81, 3))
    assert data_pointer(state.positions) == pointer and not state.positions.any()


def test_arrays_keep_their_state_alive():
    state = small_cloth().initial_state()
    x = state.positions
    expected = x.copy()
    del state
    gc.collect()
    np.testing.assert_array_equal(x, expected)


def test_errors_name_the_parameter():
    with pytest.raises(drape.InvalidParameter, match="'shear.stiffness'") as error:
        drape.Cloth(drape.ClothSpec(shear=(-1.0, 5.0)))
    assert isinstance(error.value, ValueError)
    assert error.value.parameter == "shear.stiffness" and error.value.value == "-1" and "0" in error.value.allowed
    with pytest.raises(ValueError, match="'nx' = 1 is invalid"):
        drape.ClothSpec(nx=1).validate()
    with pytest.raises(ValueError, match="'dt' = 0 is invalid; allowed: finite and > 0"):
        drape.Rk2(small_cloth(), dt=0.0)
    with pytest.raises(ValueError, match="'solver' = 'nope'.*cg, bicgstab"):
        drape.ImplicitOptions(solver="nope")
    with pytest.raises(ValueError, match="'collider radius' = -1"):
        drape.Collider.sphere((0, 0, 0), -1.0)
    with pytest.raises(ValueError, match="'boundary_condition' = 'three-corners'"):
        drape.ClothSpec(boundary="three-corners")
    with pytest.raises(ValueError, match="'pinned node' = 81"):
        drape.Rk2(small_cloth()).pins.pin(81)
    with pytest.raises(ValueError, match="'state' = 1089 nodes"):
        drape.Rk2(small_cloth()).step(drape.Cloth().initial_state())
    with pytest.raises(ValueError, match="'seconds' = -1"):
        drape.Rk2(small_cloth()).run(small_cloth().initial_state(), -1.0)
    with pytest.raises(ValueError, match="'colliders\\[0\\]'"):  # touches a pinned node
        drape.Cloth(drape.ClothSpec(colliders=[drape.Collider.sphere((0, 0, 0), 0.5)]))
    with pytest.raises(ValueError, match="'air drag' = -1"):
        drape.Cloth(drape.ClothSpec(air=drape.AirSettings(drag=-1.0)))


def test_a_failed_step_raises_and_leaves_the_state_unchanged():
    cloth = small_cloth(structural=(1e9, 0.0))
    rk2 = drape.Rk2(cloth, dt=0.01, threads=1)
    state = cloth.initial_state()
    state.positions[40, 1] = 0.05
    with pytest.raises(drape.SimulationError, match="non-finite state") as error:
        rk2.run(state, 10.0)
    assert isinstance(error.value, RuntimeError)
    assert state.all_finite()
    before = state.positions.copy(), state.velocities.copy(), state.time
    with pytest.raises(drape.SimulationError):
        rk2.step(state)
    assert np.array_equal(before[0], state.positions) and state.time == before[2]


def test_run_releases_the_gil():
    cloth = drape.Cloth(drape.ClothSpec(nx=33, ny=33))
    rk2 = drape.Rk2(cloth, threads=1)
    state = cloth.initial_state()
    steps_per_second = 1 / rk2.dt
    # Time one step so the run lasts about 0.5 s of wall time whatever the machine.
    start = time.perf_counter()
    rk2.run(state, 20 * rk2.dt)
    per_step = (time.perf_counter() - start) / 20
    seconds = max(0.5 / per_step, 100) / steps_per_second
    ticks = 0
    worker = threading.Thread(target=rk2.run, args=(state, seconds))
    worker.start()
    while worker.is_alive():  # runs only if run() lets go of the GIL
        ticks += 1
        time.sleep(0.001)
    worker.join()
    assert ticks > 50, f"the main thread ran {ticks} times while run() worked"


def test_one_state_cannot_be_stepped_twice_at_once():
    cloth = small_cloth()
    rk2 = drape.Rk2(cloth, threads=1)
    state = cloth.initial_state()

    def step_again(s):
        with pytest.raises(RuntimeError, match="being stepped"):
            rk2.step(s)
        return False

    assert rk2.run(state, 0.01, step_again) == 1


def test_run_calls_back_per_step_or_per_frame():
    cloth = small_cloth()
    rk2 = drape.Rk2(cloth, dt=0.001, threads=1)
    state = cloth.initial_state()
    times = []
    assert rk2.run(state, 0.01, lambda s: times.append(s.time)) == 10
    assert len(times) == 10 and times[-1] == state.time
    frames = []
    assert rk2.run(state, 0.1, lambda s: frames.append(round(s.time, 9)), frame_time=0.025) == 100
    assert frames == [0.035, 0.06, 0.085, 0.11]
    # Writing in the callback changes what the next step starts from.
    def stop_node(s):
        s.velocities[80] = 0.0
        s.positions[80] = (9.0, 9.0, 9.0)

    rk2.run(state, 0.003, stop_node)
    assert tuple(state.positions[80]) == (9.0, 9.0, 9.0)


def test_integrators_and_implicit_options():
    cloth = drape.Cloth(drape.ClothSpec(nx=17, ny=17))
    options = drape.ImplicitOptions(dt=1 / 60, solver="cg", preconditioner="block-jacobi", tolerance=1e-8)
    implicit = drape.ImplicitEuler(cloth, options, threads=1)
    assert implicit.options.preconditioner == "block-jacobi" and implicit.dt == pytest.approx(1 / 60)
    state = cloth.initial_state()
    status = implicit.step(state)
    assert status.iterations > 0 and status.residual <= 1e-8
    symplectic = drape.SymplecticEuler(cloth, drape.IntegratorOptions(dt=2e-4, threads=1))
    symplectic.run(state, 0.01)
    made = drape.make_integrator(cloth, "implicit", drape.ImplicitOptions(dt=0.01, solver="ldlt"))
    assert isinstance(made, drape.ImplicitEuler)
    made.step(state)
    assert state.all_finite()


def test_moving_pins_follow_their_paths():
    cloth = small_cloth(pinned_nodes=[])
    integrator = drape.ImplicitEuler(cloth, dt=0.01, threads=1)
    path = drape.PinPath.keyframes([0.0, 0.5], [(0, 0, 0), (0, 1, 0)], "linear")
    integrator.pins.pin(0, path)
    integrator.pins.pin(8, drape.PinPath.callback(lambda t: (0.8, 0.0, -t)))
    assert integrator.pins.nodes == [0, 8]
    state = cloth.initial_state()
    integrator.run(state, 0.3)
    np.testing.assert_allclose(state.positions[0], path.position(state.time), atol=1e-12)
    np.testing.assert_allclose(state.positions[8], (0.8, 0.0, -state.time), atol=1e-12)
    assert integrator.pins.release(8) and not integrator.pins.is_pinned(8)


def test_an_error_in_a_pin_function_is_raised_after_the_step():
    cloth = small_cloth()
    rk2 = drape.Rk2(cloth, threads=1)

    def broken(t):
        raise KeyError("no such path")

    rk2.pins.pin(4, drape.PinPath.callback(broken))
    state = cloth.initial_state()
    with pytest.raises(KeyError, match="no such path"):
        rk2.step(state)
    assert state.time == 0 and state.all_finite()


def test_colliders_air_and_a_scene_of_two_cloths():
    floor = drape.Collider.plane((0, -1.0, 0), (0, 1, 0)).set_friction(0.5)
    ball = drape.Collider.sphere((0.4, -0.6, 0.4), 0.3)
    assert floor.kind == "plane" and floor.static_friction == 0.5 == floor.kinetic_friction
    distance, normal, _ = ball.query((0.4, 0.0, 0.4))
    assert distance == pytest.approx(0.3) and normal == pytest.approx((0, 1, 0))
    air = drape.AirSettings(wind=(3, 0, 0), drag=0.01, gusts=drape.GustSettings(amplitude=1.0))
    lower = drape.ClothSpec(nx=9, ny=9, pinned_nodes=[], colliders=[floor, ball], air=air)
    upper = drape.ClothSpec(nx=9, ny=9, pinned_nodes=[], colliders=[floor, ball],
                            placement=drape.Placement((0.1, 0.2, 0.1), (0, 30, 0)))
    assert drape.Cloth(lower).force_terms == ["air drag"]
    scene = drape.ClothScene([lower, upper], "implicit", drape.ImplicitOptions(dt=1 / 60, threads=1),
                             drape.SelfCollisionSettings(enabled=True))
    assert scene.cloth_count == 2 and scene.node_offset(1) == 81
    x = scene.state(1).positions
    scene.run(1.0)
    assert scene.time == pytest.approx(1.0)
    assert x.min(axis=0)[1] > -1.0 - 1e-9  # the floor holds the upper cloth
    assert scene.integrator(0).contact_report.contacts > 0
    with pytest.raises(IndexError):
        scene.state(2)


def jittered_patch(n=8, h=0.05, seed=3):
    """An n x n patch h apart in the x-z plane, interior vertices moved, cells split at random."""
    rng = np.random.default_rng(seed)
    i, j = np.meshgrid(np.arange(n, dtype=float), np.arange(n, dtype=float))
    x, z = i.ravel(), j.ravel()
    interior = (x > 0) & (x < n - 1) & (z > 0) & (z < n - 1)
    x[interior] += rng.uniform(-0.25, 0.25, interior.sum())
    z[interior] += rng.uniform(-0.25, 0.25, interior.sum())
    vertices = np.column_stack([x * h, np.zeros(n * n), z * h])
    triangles = []
    for jj in range(n - 1):
        for ii in range(n - 1):
            a, b, c, d = jj * n + ii, jj * n + ii + 1, (jj + 1) * n + ii + 1, (jj + 1) * n + ii
            triangles += [[a, d, c], [a, c, b]] if rng.random() < 0.5 else [[a, d, b], [b, d, c]]
    return vertices, np.array(triangles, dtype=np.int32)


def test_a_cloth_of_any_mesh_from_numpy_hangs_from_its_pins():
    vertices, triangles = jittered_patch()
    spec = drape.ClothSpec.from_mesh(vertices, triangles)
    assert spec.has_mesh
    spec.pinned_nodes = [0, 7]
    spec.areal_density = 0.2
    spec.bending = 1e-4
    spec.springs.structural.stiffness, spec.springs.shear.stiffness, spec.springs.bend.stiffness = 200, 50, 5
    cloth = drape.Cloth(spec)
    assert cloth.node_count == 64 and np.array_equal(cloth.triangles, triangles)
    state = cloth.initial_state()
    np.testing.assert_array_equal(state.positions, vertices)
    drape.ImplicitEuler(cloth, dt=0.01).run(state, 1.0)
    assert np.isfinite(state.positions).all()
    assert state.positions[63, 1] < -0.2  # the far corner has swung down
    np.testing.assert_array_equal(state.positions[[0, 7]], vertices[[0, 7]])


def test_a_bad_mesh_names_the_element():
    vertices, triangles = jittered_patch()
    triangles[5, 2] = 64
    with pytest.raises(drape.InvalidParameter, match=r"mesh\.triangles\[5\]"):
        drape.Cloth(drape.ClothSpec.from_mesh(vertices, triangles))
    with pytest.raises(drape.InvalidParameter, match="rest_uv"):
        drape.ClothSpec.from_mesh(vertices, triangles, rest_uv=np.zeros((3, 2)))
def test_cylinder_collider_a_round_table():
    table = drape.Collider.cylinder((0.4, -0.4, 0.4), 0.2, 0.1, rounding=0.05).set_friction(0.3)
    assert (table.kind, table.radius, table.half_height, table.rounding) == ("cylinder", 0.2, 0.1, 0.05)
    distance, normal, _ = table.query((0.4, 0.0, 0.4))
    assert distance == pytest.approx(0.3) and normal == pytest.approx((0, 1, 0))
    lying = drape.Collider.cylinder((0, 0, 0), 0.5, 1.0, rotation=[(1, 0, 0), (0, 0, -1), (0, 1, 0)])
    distance, normal, _ = lying.query((0, 0, 3))  # its axis along z: 2 m from its cap
    assert distance == pytest.approx(2.0) and normal == pytest.approx((0, 0, 1))
    with pytest.raises(drape.InvalidParameter, match="'collider rounding'"):
        drape.Collider.cylinder((0, 0, 0), 1.0, 0.5, rounding=0.6)
    # A cloth dropped on it: its middle rests on the top, the rest hangs over the rim.
    cloth = drape.Cloth(drape.ClothSpec(nx=9, ny=9, pinned_nodes=[], colliders=[table]))
    state = cloth.initial_state()
    drape.ImplicitEuler(cloth, dt=0.01, threads=1).run(state, 1.0)
    y = state.positions[:, 1]
    assert y[4 * 9 + 4] == pytest.approx(-0.3 + 0.005, abs=1e-3)
    assert y.min() < -0.4


def cube(half):
    """A cube's 8 corners and 12 triangles, counter-clockwise seen from outside."""
    v = np.array([[x, y, z] for z in (-half, half) for y in (-half, half) for x in (-half, half)], dtype=float)
    quads = [(0, 2, 3, 1), (4, 5, 7, 6), (0, 1, 5, 4), (2, 6, 7, 3), (1, 3, 7, 5), (0, 4, 6, 2)]
    t = np.array([tri for a, b, c, d in quads for tri in ((a, b, c), (a, c, d))], dtype=np.int32)
    return v, t


def test_mesh_collider_still_and_animated(tmp_path):
    v, t = cube(0.2)
    box = drape.Collider.mesh(v, t, center=(0.1, -0.4, 0.1)).set_friction(0.3)
    assert box.kind == "mesh" and not box.deforms
    distance, normal, _ = box.query((0.1, 0.0, 0.1))
    assert distance == pytest.approx(0.2) and normal == pytest.approx((0, 1, 0))
    raised = v + (0, 1, 0)
    lift = drape.Collider.animated_mesh([v, raised], t, [0.0, 2.0])
    assert lift.deforms
    distance, _, velocity = lift.query((0, 1.0, 0), 1.0)
    assert distance == pytest.approx(0.3) and velocity == pytest.approx((0, 0.5, 0))
    with pytest.raises(drape.InvalidParameter, match="collider frame times"):
        drape.Collider.animated_mesh([v, raised], t, [1.0, 0.5])
    with pytest.raises(drape.InvalidParameter, match="collider mesh"):
        drape.Collider.mesh(v, t[:, ::-1].copy())  # wound inward
    obj = tmp_path / "cube.obj"
    obj.write_text("".join("v %g %g %g\n" % tuple(p) for p in v) + "".join("f %d %d %d\n" % tuple(f + 1) for f in t))
    assert drape.Collider.from_obj(str(obj), scale=2.0).query((0, 1.0, 0))[0] == pytest.approx(0.6)
    # A cloth dropped on the still cube rests on its top.
    cloth = drape.Cloth(drape.ClothSpec(nx=5, ny=5, spacing=0.05, pinned_nodes=[], colliders=[box]))
    state = cloth.initial_state()
    drape.ImplicitEuler(cloth, dt=0.01, threads=1).run(state, 1.0)
    assert state.positions[:, 1].max() == pytest.approx(-0.2 + 0.005, abs=1e-3)
