"""Garments from sewing patterns (drape.load_pattern): GarmentCode's T-shirt as a cloth spec whose
seams pull the panels together, and bad patterns and settings named."""

import json

import numpy as np
import pytest

import drape

from conftest import SCENES

SHIRT = SCENES / "garments" / "shirt_mean.json"


def test_the_shirt_pattern_becomes_a_cloth_with_seams_and_delayed_gravity():
    spec = drape.load_pattern(str(SHIRT), edge_length=0.03, fabric="denim", seam_closing_time=0.5)
    assert spec.has_mesh
    assert spec.gravity == 0  # carried by the ramped-gravity term, after the seams close
    assert spec.self_collision.enabled
    pairs = spec.self_collision.joined_nodes
    assert len(pairs) > 50
    cloth = drape.Cloth(spec)
    assert set(cloth.force_terms) == {"seams", "dihedral bending", "seam hinges", "ramped gravity"}
    triangles = cloth.triangles
    assert triangles.shape[1] == 3 and triangles.min() == 0 and triangles.max() == cloth.node_count - 1

    # Without a body the seams still close: the widest gap shrinks as the rest lengths ramp down.
    def widest(positions):
        return max(np.linalg.norm(positions[a] - positions[b]) for a, b in pairs)

    state = cloth.initial_state()
    start = widest(np.array(state.positions))
    drape.ImplicitEuler(cloth, dt=1 / 60, threads=1).run(state, 0.25)
    assert widest(np.array(state.positions)) < 0.75 * start
    # No gravity yet: the garment's centre of mass has not fallen.
    assert abs(np.mean(np.array(state.positions)[:, 1] - np.array(cloth.start_positions)[:, 1])) < 0.01


def test_bad_patterns_and_settings_are_named(tmp_path):
    pattern = json.loads(SHIRT.read_text())
    pattern["pattern"]["stitches"][7][1]["panel"] = "no_such_panel"
    bad = tmp_path / "bad.json"
    bad.write_text(json.dumps(pattern))
    with pytest.raises(drape.PatternError, match=r"stitches\[7\]\[1\]"):
        drape.load_pattern(str(bad))
    with pytest.raises(drape.InvalidParameter, match="fabric"):
        drape.load_pattern(str(SHIRT), fabric="tweed")
    with pytest.raises(drape.InvalidParameter, match="seam stiffness"):
        drape.load_pattern(str(SHIRT), seam_stiffness=-1.0)


def test_panel_offsets_move_one_panel_from_the_patterns_placement():
    plain = drape.Cloth(drape.load_pattern(str(SHIRT), edge_length=0.03))
    moved = drape.Cloth(drape.load_pattern(str(SHIRT), edge_length=0.03, panel_offsets={"left_sleeve_f": (0.06, -0.02, 0.01)}))
    shift = np.array(moved.start_positions) - np.array(plain.start_positions)
    on_panel = np.linalg.norm(shift - np.array([0.06, -0.02, 0.01]), axis=1) < 1e-12
    still = np.linalg.norm(shift, axis=1) == 0
    assert on_panel.sum() > 20  # the sleeve's vertices, moved by the offset
    assert np.all(on_panel | still)  # every other vertex where the pattern places it
    with pytest.raises(drape.InvalidParameter, match="panel offsets.*left_sleeve'.*left_sleeve_f"):
        drape.load_pattern(str(SHIRT), panel_offsets={"left_sleeve": (0.06, 0.0, 0.0)})
    with pytest.raises(drape.InvalidParameter, match="panel offsets"):
        drape.load_pattern(str(SHIRT), panel_offsets={"left_sleeve_f": (float("nan"), 0.0, 0.0)})
