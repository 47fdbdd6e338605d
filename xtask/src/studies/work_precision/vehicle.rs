//! The work–precision section's Iltis vehicle (scene C, `models/iltis_vehicle.ron`): its
//! beams switched flexible ([`vehicle_flexible`]), judged on the heights of the chassis and
//! of the front-left wheel against `flexmbd tune`'s default reference (here the richest
//! model at a quarter of the smallest step), over both formulations and
//! inertia routes, 0 to 2 fixed-interface modes per beam and their kind; shortened in
//! --quick ([`vehicle_plan`]).

use flexmbd::fe::ModeSelection;
use flexmbd::model::Stiffening;
use flexmbd::sweep::{Reference, Sweep, basis_name};
use flexmbd_test_support::iltis::{VEHICLE_BEAMS, vehicle_flexible};

use super::{Case, TOLERANCES, grid};

/// What the vehicle's sweep runs: how many of its beams are flexible ([`vehicle_flexible`]),
/// for how long (`None`: the file's 8 s), with which mode counts and kinds.
struct VehiclePlan {
    beams: usize,
    duration: Option<f64>,
    modes: Vec<usize>,
    bases: Vec<ModeSelection>,
}

/// The vehicle's plan. --quick: the first second (the front axle up the ramp) with the
/// four beams of the flexible Iltis section's 4-body case (the front-left corner, whose
/// wheel is judged, and the front-right A-arm), 0 and 2 modes, the lowest modes, the
/// Ritz vectors and the proper orthogonal modes. Most of the cost is the absolute formulation's (0.5 s of CPU per simulated
/// second with every beam rigid, 0.9 s with all 12 flexible, and its static equilibrium
/// before every run), and `tune` times every candidate of each kind alone.
fn vehicle_plan(quick: bool) -> VehiclePlan {
    if quick {
        VehiclePlan {
            beams: 4,
            duration: Some(1.0),
            modes: vec![0, 2],
            bases: vec![
                ModeSelection::LowestFrequency,
                ModeSelection::LoadRitz,
                ModeSelection::ProperOrthogonal,
            ],
        }
    } else {
        VehiclePlan {
            beams: VEHICLE_BEAMS.len(),
            duration: None,
            modes: vec![0, 1, 2],
            bases: ModeSelection::ALL.to_vec(),
        }
    }
}

/// The Iltis vehicle (scene C) with the plan's beams flexible, judged on the heights of the
/// chassis and of the front-left wheel against `flexmbd tune`'s default reference.
pub(super) fn vehicle_case(quick: bool, steps: &[f64]) -> Result<Case, Box<dyn std::error::Error>> {
    let plan = vehicle_plan(quick);
    let sweep = vehicle_sweep(&plan, steps);
    let span = plan
        .duration
        .map_or("8 s".to_string(), |d| format!("its first {d} s of 8"));
    Ok(Case {
        note: Some(vehicle_note(&plan, steps)),
        bases: plan.bases,
        basis_tolerances: &TOLERANCES,
        basis_where: "the vehicle's beams",
        basis_note: "",
        spreads: true,
        ..Case::plain(
            "iltis_vehicle",
            &format!(
                "Iltis vehicle (scene C), {} flexible beams, {span}",
                plan.beams
            ),
            "the heights of the chassis's centre of mass and of the front-left wheel centre \
             (`chassis_z`, `wheel_fl_z`, the larger); linear elasticity, one stiffening method",
            sweep,
        )
    })
}

/// The plan's sweep of scene C over `steps`, its reference still to be made.
fn vehicle_sweep(plan: &VehiclePlan, steps: &[f64]) -> Sweep {
    let mut sets = vehicle_flexible(plan.beams);
    if let Some(d) = plan.duration {
        sets.push(format!("solver.duration={d}"));
    }
    Sweep {
        scene: crate::workspace_root().join("models/iltis_vehicle.ron"),
        sets,
        sensors: vec!["chassis_z".into(), "wheel_fl_z".into()],
        reference: Reference::Faithful,
        grid: grid(&[Stiffening::Linear], &plan.bases, &plan.modes, steps),
        error_cap: None,
        reference_cache: None,
    }
}

/// What the subsection says of the scene, its grid and its reference.
fn vehicle_note(plan: &VehiclePlan, steps: &[f64]) -> String {
    let mut note = format!(
        "Scene C (`models/iltis_vehicle.ron`): the vehicle at 5 m/s from its static \
         equilibrium over the ramp and steps, its first {} beam bodies flexible ({}; `--set \
         bodies.NAME.flexible=true`, docs/scenes.md §3.4). Grid: both formulations, both \
         inertia routes, linear elasticity only (the scene's own; one stiffening method), {} \
         fixed-interface modes per flexible beam beside its static modes (0: the static modes \
         alone; the kind then names nothing, and those runs are one model run once per kind), \
         their kind ({}), steps {}. No model of another family follows this scene (the ANCF \
         cable models one beam on a hub, and substructuring splits straight beams along \
         their body x from the origin, which the links are not), so `flexmbd tune`'s default \
         reference is the grid's richest model at a quarter of its smallest step, a model of \
         the runs' own family; its margin covers its step, not its modelling error.",
        plan.beams,
        VEHICLE_BEAMS[..plan.beams].join(", "),
        list(&plan.modes.iter().map(usize::to_string).collect::<Vec<_>>()),
        plan.bases
            .iter()
            .map(|&k| basis_name(k))
            .collect::<Vec<_>>()
            .join(", "),
        list(&steps_text(steps)),
    );
    if let Some(d) = plan.duration {
        note.push_str(&format!(
            " *Quick run:* scene C is shortened to its first {d} s of 8 (the front axle up the \
             ramp; the rear axle reaches it at 1.0 s, the steps down later) with {} of its {} \
             beams flexible and {} modes{}.",
            plan.beams,
            VEHICLE_BEAMS.len(),
            list(&plan.modes.iter().map(usize::to_string).collect::<Vec<_>>()),
            if plan.bases.contains(&ModeSelection::Participation) {
                ""
            } else {
                ", without the participation ranking"
            },
        ));
    }
    note
}

/// "a, b and c".
fn list(items: &[String]) -> String {
    match items {
        [] => String::new(),
        [one] => one.clone(),
        [rest @ .., last] => format!("{} and {last}", rest.join(", ")),
    }
}

/// The steps of a grid about h = 1 ms as a reader names them (2h, h, h/2).
fn steps_text(steps: &[f64]) -> Vec<String> {
    steps
        .iter()
        .map(|&s| {
            let r = s / 1e-3;
            if (r - 1.0).abs() < 1e-9 {
                "h".to_string()
            } else if r > 1.0 {
                format!("{r}h")
            } else {
                format!("h/{}", 1.0 / r)
            }
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use flexmbd::sweep::Setting;

    /// The flexible beams a grid's modes axis changes, and the number of points.
    fn grid_of(quick: bool) -> (Vec<String>, usize) {
        let points = vehicle_sweep(&vehicle_plan(quick), &[2e-3, 1e-3])
            .point_settings()
            .unwrap();
        let bodies = points[0]
            .iter()
            .find_map(|s| match s {
                Setting::Modes { bodies, .. } => Some(bodies.clone()),
                _ => None,
            })
            .unwrap();
        (bodies, points.len())
    }

    #[test]
    fn the_vehicle_grids_switch_the_planned_beams_of_scene_c_flexible() {
        let (bodies, n) = grid_of(true);
        let mut expected: Vec<String> = VEHICLE_BEAMS[..4].iter().map(|b| b.to_string()).collect();
        expected.sort();
        let mut bodies = bodies;
        bodies.sort();
        assert_eq!(bodies, expected);
        // formulations x routes x kinds x modes x steps
        assert_eq!(n, 2 * 2 * 3 * 2 * 2);
        let (bodies, n) = grid_of(false);
        assert_eq!(bodies.len(), VEHICLE_BEAMS.len());
        assert_eq!(n, 2 * 2 * 4 * 3 * 2);
    }

    #[test]
    fn steps_and_lists_read_as_a_reader_names_them() {
        assert_eq!(steps_text(&[2e-3, 1e-3, 5e-4]), ["2h", "h", "h/2"]);
        let items = |v: &[&str]| v.iter().map(|s| s.to_string()).collect::<Vec<_>>();
        assert_eq!(list(&items(&["0", "1", "2"])), "0, 1 and 2");
        assert_eq!(list(&items(&["2h", "h"])), "2h and h");
        assert_eq!(list(&items(&["h"])), "h");
    }
}
