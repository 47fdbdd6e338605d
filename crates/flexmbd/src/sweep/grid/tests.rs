//! The grid's parsing, product and richest point.

use super::*;

fn spin_up() -> Scene {
    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../models/spin_up_beam_2d.ron"
    );
    Scene::load(path).unwrap()
}

#[test]
fn points_are_in_grid_order_with_the_last_axis_fastest() {
    let grid = Grid {
        axes: vec![
            Axis::Formulation(vec![FormulationKind::Absolute, FormulationKind::Relative]),
            Axis::Step(vec![1e-3, 5e-4, 2.5e-4]),
        ],
    };
    let points = grid.points(&spin_up(), &[]).unwrap();
    let labels: Vec<String> = points.iter().map(GridPoint::label).collect();
    assert_eq!(
        labels,
        [
            "absolute h=0.001",
            "absolute h=0.0005",
            "absolute h=0.00025",
            "relative h=0.001",
            "relative h=0.0005",
            "relative h=0.00025"
        ]
    );
    assert!(points.iter().enumerate().all(|(k, p)| p.index == k));
}

#[test]
fn a_point_is_the_simulate_arguments_and_the_scene_they_make() {
    let grid = Grid {
        axes: vec![
            Axis::Stiffening(vec![Stiffening::Foreshortening]),
            Axis::Modes {
                body: None,
                counts: vec![3],
            },
            Axis::Step(vec![5e-4]),
        ],
    };
    let scene = spin_up();
    let point = &grid.points(&scene, &[]).unwrap()[0];
    let sets = vec!["solver.duration=2".to_string()];
    assert_eq!(
        point.args("models/spin_up_beam_2d.ron", &sets),
        [
            "models/spin_up_beam_2d.ron",
            "--set",
            "solver.duration=2",
            "--stiffening",
            "foreshortening",
            "--set",
            "bodies.beam.model.Beam.normal_modes=3",
            "--set",
            "solver.step=0.0005"
        ]
    );
    let varied = point.scene(&scene, &sets).unwrap();
    assert_eq!(varied.solver.stiffening, Stiffening::Foreshortening);
    assert_eq!(varied.solver.step, 5e-4);
    assert_eq!(varied.solver.duration, 2.0);
    let BodyModel::Beam(spec) = &varied.bodies[0].model else {
        panic!("the spin-up beam is a beam")
    };
    assert_eq!(spec.normal_modes, 3);
}

#[test]
fn a_basis_point_sets_the_mode_selection_of_every_flexible_beam() {
    let grid = Grid {
        axes: vec![Axis::Basis {
            body: None,
            kinds: vec![ModeSelection::LowestFrequency, ModeSelection::LoadRitz],
        }],
    };
    let scene = spin_up();
    let points = grid.points(&scene, &[]).unwrap();
    let labels: Vec<String> = points.iter().map(GridPoint::label).collect();
    assert_eq!(labels, ["basis=lowest", "basis=ritz"]);
    assert_eq!(
        points[1].args("s.ron", &[]),
        [
            "s.ron",
            "--set",
            "bodies.beam.model.Beam.mode_selection=LoadRitz"
        ]
    );
    let BodyModel::Beam(spec) = &points[1].scene(&scene, &[]).unwrap().bodies[0].model else {
        panic!("the spin-up beam is a beam")
    };
    assert_eq!(spec.mode_selection, ModeSelection::LoadRitz);
    assert_eq!(
        parse_basis("participation"),
        Some(ModeSelection::Participation)
    );
    assert_eq!(parse_basis("krylov"), None);
}

#[test]
fn a_modes_axis_may_keep_the_static_modes_alone() {
    let scene = spin_up();
    let grid = Grid {
        axes: vec![Axis::Modes {
            body: None,
            counts: vec![0, 2],
        }],
    };
    let points = grid.points(&scene, &[]).unwrap();
    assert_eq!(points[0].label(), "modes=0");
    let BodyModel::Beam(spec) = &points[0].scene(&scene, &[]).unwrap().bodies[0].model else {
        panic!("the spin-up beam is a beam")
    };
    assert_eq!(spec.normal_modes, 0);
}

#[test]
fn empty_grids_and_bad_axis_values_are_refused_by_name() {
    let scene = spin_up();
    let refused = |axes: Vec<Axis>| Grid { axes }.points(&scene, &[]).unwrap_err().to_string();
    assert!(refused(vec![]).contains("empty grid"));
    let e = refused(vec![Axis::Step(vec![])]);
    assert!(e.contains("step") && e.contains("no values"), "{e}");
    let e = refused(vec![Axis::Step(vec![1e-3, -1e-3])]);
    assert!(e.contains("-0.001"), "{e}");
    let e = refused(vec![Axis::Modes {
        body: Some("hub".into()),
        counts: vec![2],
    }]);
    assert!(e.contains("`hub` is not a flexible beam body"), "{e}");
    let e = refused(vec![Axis::Elements {
        body: None,
        counts: vec![0],
    }]);
    assert!(
        e.contains("elements") && e.contains("0 is not a count"),
        "{e}"
    );
}

#[test]
fn the_richest_point_has_the_most_modes_and_the_smallest_step() {
    let grid = Grid {
        axes: vec![
            Axis::Formulation(vec![FormulationKind::Relative, FormulationKind::Absolute]),
            Axis::Modes {
                body: None,
                counts: vec![2, 4, 3],
            },
            Axis::Step(vec![1e-3, 2.5e-4, 5e-4]),
        ],
    };
    assert_eq!(
        grid.richest(&spin_up(), &[]).unwrap().label(),
        "relative modes=4 h=0.00025"
    );
}
