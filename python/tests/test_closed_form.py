"""Closed-form motions through the package, the scene built from dicts.

The time scheme (docs/math.md §1.1, Newmark beta = 1/2, gamma = 1) is exact for motion under a
constant force: the position after n steps is the parabola's at t = n dt, whatever dt. So the
tolerances are the solver's, not the scheme's: 1e-9 m, as tests/rock/joint_provenance.rs argues
(tolerance 1e-12 relative on forces of ~10 kN, times dt^2 / m).
"""

import math

import pytest

import pbdda

G = 9.81


def sliding_block(slope_deg: float, phi_deg: float) -> dict:
    """A 1 m square rigid block on a fixed base, gravity tilted by the slope angle (the base is
    the slope), the interface of friction angle phi."""
    a = math.radians(slope_deg)
    return {
        "scene": {"name": "block on an incline"},
        "time": {"step": 0.01, "steps": 30},
        "physics": {"gravity": [G * math.sin(a), -G * math.cos(a)]},
        "solver": {"tolerance": 1e-12},
        "material": [{"name": "rock", "density": 1000.0}],
        "interface": [{"friction_angle": phi_deg}],
        "body": [
            {
                "name": "base",
                "shape": "polygon",
                "vertices": [[-5.0, -1.0], [5.0, -1.0], [5.0, 0.0], [-5.0, 0.0]],
                "material": "rock",
                "fixed": True,
            },
            {
                "name": "block",
                "shape": "polygon",
                "vertices": [[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]],
                "material": "rock",
            },
        ],
    }


def block(sim):
    b = sim.bodies()
    return b[b["body"] == "block"][0]


def test_block_slides_down_the_incline():
    """Slope 30°, phi = 20°: s(t) = g (sin a - cos a tan phi) t^2 / 2 along the slope, at every
    step; the contact's normal force is the block's weight component m g cos a (m = 1000 kg),
    to the solver's relative tolerance (1e-9 of 8.5 kN)."""
    a, phi = math.radians(30.0), math.radians(20.0)
    acc = G * (math.sin(a) - math.cos(a) * math.tan(phi))
    sim = pbdda.from_dict(sliding_block(30.0, 20.0))
    x0 = block(sim)["x"]
    for n in range(1, 31):
        assert sim.step() == 1
        t = n * 0.01
        assert sim.time == pytest.approx(t, rel=1e-12)
        s = block(sim)["x"] - x0
        assert abs(s - 0.5 * acc * t * t) < 1e-9, (n, s, 0.5 * acc * t * t)
    contacts = sim.contacts()
    assert len(contacts) > 0
    weight = 1000.0 * G * math.cos(a)
    assert abs(contacts["normal_force"].sum() - weight) < 1e-9 * weight


def test_block_below_its_friction_angle_stays():
    """Slope 20°, phi = 30°: friction holds the block; it does not move (1e-9 m)."""
    sim = pbdda.from_dict(sliding_block(20.0, 30.0))
    x0 = block(sim)["x"]
    sim.run()
    assert sim.finished and sim.step_index == 30
    assert abs(block(sim)["x"] - x0) < 1e-9


def test_free_falling_disk_and_run_to():
    """A disk alone under g = 9.81: y(t) = y0 - g t^2 / 2 and vy = -g t exactly (1e-9). run_to
    stops at the first step that reaches the time asked: 0.25 s with dt = 0.01 s is step 25."""
    scene = {
        "scene": {"name": "free fall"},
        "time": {"step": 0.01, "steps": 100},
        "physics": {"gravity": [0.0, -G]},
        "material": [{"name": "m", "density": 2000.0}],
        "body": [{"name": "disk", "shape": "disk", "center": [0.0, 10.0], "radius": 0.5, "material": "m"}],
    }
    sim = pbdda.from_dict(scene)
    assert sim.run_to(0.25) == 25
    t = sim.time
    assert t == pytest.approx(0.25, rel=1e-12)
    d = sim.bodies()[0]
    assert abs(d["y"] - (10.0 - 0.5 * G * t * t)) < 1e-9
    assert abs(d["vy"] + G * t) < 1e-9
    assert d["x"] == 0.0 and d["vx"] == 0.0
