//! Valid scenes: the full scene field by field, the contract's defaults, `end`, integer literals.

use super::*;

// ------------------------------------------------------------------ valid scenes

#[test]
fn full_scene_gives_expected_model() {
    let m = ok(FULL);
    assert_eq!(m.name, "full");
    assert_eq!((m.time.step, m.time.steps), (0.001, 100));
    assert_eq!(m.physics.gravity, v(0.0, -10.0));
    assert_eq!(m.physics.plane, Plane::Strain);
    assert_eq!(m.physics.velocity_carry, 0.5);
    assert_eq!(m.contact.threshold, Some(0.05));
    assert_eq!((m.solver.tolerance, m.solver.max_iterations), (1e-10, 5000));
    assert_eq!(m.output.every, 10);

    assert_eq!(m.materials.len(), 2);
    let rock = &m.materials[0];
    assert_eq!((rock.name.as_str(), rock.density), ("rock", 2500.0));
    assert_eq!((rock.young, rock.poisson), (Some(1.0e10), Some(0.25)));
    let steel = &m.materials[1];
    assert_eq!((steel.name.as_str(), steel.density), ("steel", 7800.0));
    assert_eq!((steel.young, steel.poisson), (None, None));

    assert_eq!(m.interfaces.len(), 2);
    let default = &m.interfaces[0];
    assert_eq!(default.materials, None);
    assert_eq!((default.friction, default.cohesion), (0.3, 1.0));
    assert_eq!((default.tensile_strength, default.rolling), (2.0, 0.01));
    let pair = &m.interfaces[1];
    assert_eq!(pair.materials, Some([1, 0]));
    assert!((pair.friction - 1.0).abs() < 1e-15, "tan 45° = {}", pair.friction);
    assert_eq!((pair.cohesion, pair.tensile_strength, pair.rolling), (0.0, 0.0, 0.0));
}

#[test]
fn full_scene_bodies_loads_monitors() {
    let m = ok(FULL);
    assert_eq!(m.bodies.len(), 3);
    let d1 = &m.bodies[0];
    assert_eq!(d1.name, "d1");
    assert_eq!(d1.shape, Shape::Disk { center: v(0.0, 10.0), radius: 10.0 });
    assert_eq!((d1.model, d1.material, d1.fixed), (BodyModel::Rigid, 0, false));
    assert_eq!((d1.velocity, d1.angular_velocity), (v(1.0, -2.0), 0.5));
    assert_eq!(d1.initial_stress, None);

    let r1 = &m.bodies[1];
    assert_eq!(r1.shape, Shape::Ring { center: v(30.0, 10.0), outer: 5.0, inner: 4.0 });
    assert_eq!((r1.model, r1.material, r1.fixed), (BodyModel::Rigid, 1, false));
    assert_eq!((r1.velocity, r1.angular_velocity), (Vec2::zeros(), 0.0));

    // the concave floor is given clockwise and must come back counter-clockwise
    let floor = &m.bodies[2];
    let ccw = vec![v(0.0, -1.0), v(1.0, -1.0), v(1.0, -0.5), v(2.0, -0.5), v(2.0, 0.0), v(0.0, 0.0)];
    assert_eq!(floor.shape, Shape::Polygon { vertices: ccw });
    assert_eq!((floor.material, floor.fixed), (0, true));

    assert_eq!(m.loads.len(), 2);
    let l = &m.loads[0];
    assert_eq!((l.body, l.point, l.force), (0, v(0.0, 10.0), v(1000.0, 0.0)));
    assert_eq!(l.history, Some(vec![(0.0, 1.0), (1.0, 0.0)]));
    let l = &m.loads[1];
    assert_eq!((l.body, l.point, l.force, l.history.clone()), (1, v(30.0, 15.0), v(0.0, -5.0), None));

    assert_eq!(m.monitors.len(), 1);
    let o = &m.monitors[0];
    assert_eq!((o.name.as_str(), o.body, o.point), ("O", 0, v(0.0, 10.0)));
}

#[test]
fn minimal_scene_gets_the_contract_defaults() {
    let m = ok(MINIMAL);
    assert_eq!((m.physics.gravity, m.physics.plane), (Vec2::zeros(), Plane::Stress));
    assert_eq!(m.physics.velocity_carry, 1.0);
    assert_eq!(m.contact.threshold, None);
    assert_eq!((m.solver.tolerance, m.solver.max_iterations), (1e-8, 200_000));
    assert_eq!(m.output.every, 1);
    assert!(m.interfaces.is_empty() && m.loads.is_empty() && m.monitors.is_empty());
}

#[test]
fn end_gives_the_number_of_steps() {
    // 0.07 / 0.01 = 7.000000000000001 in f64: the 1e-9 tolerance keeps it at 7 steps
    assert_eq!(ok(&edit(5, "end = 0.07").replace("0.001", "0.01")).time.steps, 7);
    // a partial last step is a whole step: 0.0105 / 0.001 -> 11
    assert_eq!(ok(&edit(5, "end = 0.0105")).time.steps, 11);
}

#[test]
fn integer_literals_are_accepted_for_reals() {
    assert_eq!(
        ok(&edit(13, "radius = 2")).bodies[0].shape,
        Shape::Disk { center: Vec2::zeros(), radius: 2.0 }
    );
}
