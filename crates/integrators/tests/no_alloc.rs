//! The step loop allocates nothing after set-up (counting global allocator).

use flexmbd_core::{Coordinates, Formulation, Request, State, SystemTerms};
use flexmbd_integrators::{Ali3p, Ali3pSettings};
use nalgebra::DVector;

#[global_allocator]
static GLOBAL: flexmbd_test_support::CountingAllocator = flexmbd_test_support::CountingAllocator;

/// Two point masses on rods: a double pendulum in natural coordinates (4 coordinates, 2 constraints).
struct DoublePendulum {
    coordinates: Coordinates,
}

impl DoublePendulum {
    /// Both rods along x, at rest.
    fn new() -> Self {
        let q0 = DVector::from_column_slice(&[1.0, 0.0, 2.0, 0.0]);
        DoublePendulum {
            coordinates: Coordinates::new(q0, DVector::zeros(4), 2),
        }
    }
}

impl Formulation for DoublePendulum {
    fn coordinates(&self) -> &Coordinates {
        &self.coordinates
    }
    fn evaluate(&mut self, state: State<'_>, req: Request, out: &mut SystemTerms) {
        let (q, qd) = (state.q, state.qd);
        let d = [q[2] - q[0], q[3] - q[1]];
        let dd = [qd[2] - qd[0], qd[3] - qd[1]];
        if req.dynamics {
            for i in 0..4 {
                out.mass[(i, i)] = 1.0;
            }
            out.forces[1] = -9.81;
            out.forces[3] = -9.81;
        }
        if req.constraints {
            out.phi[0] = q[0] * q[0] + q[1] * q[1] - 1.0;
            out.phi[1] = d[0] * d[0] + d[1] * d[1] - 1.0;
        }
        if req.jacobian {
            out.phi_q[(0, 0)] = 2.0 * q[0];
            out.phi_q[(0, 1)] = 2.0 * q[1];
            out.phi_q[(1, 0)] = -2.0 * d[0];
            out.phi_q[(1, 1)] = -2.0 * d[1];
            out.phi_q[(1, 2)] = 2.0 * d[0];
            out.phi_q[(1, 3)] = 2.0 * d[1];
        }
        if req.accel_term {
            out.accel_term[0] = 2.0 * (qd[0] * qd[0] + qd[1] * qd[1]);
            out.accel_term[1] = 2.0 * (dd[0] * dd[0] + dd[1] * dd[1]);
        }
    }
}

#[test]
fn steps_allocate_nothing() {
    let mut f = DoublePendulum::new();
    let mut s = Ali3p::new(&mut f, 0.0, Ali3pSettings::default()).unwrap();
    s.step(&mut f).unwrap();
    let before = flexmbd_test_support::allocations();
    for _ in 0..500 {
        s.step(&mut f).unwrap();
    }
    let after = flexmbd_test_support::allocations();
    assert_eq!(
        after - before,
        0,
        "the step loop allocated {} times",
        after - before
    );
    assert!(s.stats.newton_iterations >= 500);
}

#[test]
fn restoring_a_checkpoint_repeats_the_step_bit_for_bit_without_allocating() {
    let mut f = DoublePendulum::new();
    let mut s = Ali3p::new(&mut f, 0.0, Ali3pSettings::default()).unwrap();
    // Past the first steps, so the predictor has a history to restore.
    for _ in 0..50 {
        s.step(&mut f).unwrap();
    }
    let c = s.checkpoint();
    let bits = |s: &Ali3p| -> Vec<u64> {
        s.q.iter()
            .chain(s.qd.iter())
            .chain(s.qdd.iter())
            .chain(s.lambda.iter())
            .chain([s.t].iter())
            .map(|v| v.to_bits())
            .collect()
    };
    let run = |s: &mut Ali3p, f: &mut DoublePendulum| {
        for _ in 0..20 {
            s.step(f).unwrap();
        }
    };
    run(&mut s, &mut f);
    let (first, stats) = (bits(&s), s.stats.clone());
    let before = flexmbd_test_support::allocations();
    s.restore(&c);
    let after = flexmbd_test_support::allocations();
    assert_eq!(after - before, 0, "restore allocated");
    run(&mut s, &mut f);
    assert_eq!(bits(&s), first);
    assert_eq!(s.stats.steps, stats.steps);
    assert_eq!(s.stats.newton_iterations, stats.newton_iterations);
}
