//! The contract between a formulation (absolute or relative coordinates) and the
//! integrators (ARCHITECTURE.md, "The `Formulation` trait"; docs/methods.md §5).
//!
//! At a trial [`State`] (t, q, q̇) a formulation computes, in **one pass** over its
//! bodies, whatever [`Request`] asks for, into the [`SystemTerms`] that the
//! integrator sized once:
//!
//! - the mass matrix **M** and the generalized forces **Q** (inertial quadratic-velocity
//!   terms, gravity, springs, elastic forces);
//! - approximations of the tangents **K** = −∂Q/∂q and **C** = −∂Q/∂q̇;
//! - the constraints **Φ**, their Jacobian **Φ_q**, **Φ_t**, and the acceleration term
//!   **c** = Φ̇_q q̇ + Φ̇_t.
//!
//! Coordinates update additively, q ← q + Δq. What every formulation knows of its
//! coordinates apart from the physics — how many, how many constraint equations bind them,
//! where they start, which the user specified — is one [`Coordinates`] value it holds; the
//! trait's questions about them are answered from it once, here.
//!
//! What a simulation reads at output instants, the sensors, is a separate trait
//! ([`Observe`]); a compiled scene is both ([`CompiledScene`]).

use nalgebra::{DMatrix, DVector};

/// A trial state: the time and the coordinates and rates there, borrowed from whoever holds
/// them (the integrator, a test).
#[derive(Clone, Copy, Debug)]
pub struct State<'a> {
    /// Time t (s).
    pub t: f64,
    /// Coordinates q (n).
    pub q: &'a DVector<f64>,
    /// Rates q̇ (n).
    pub qd: &'a DVector<f64>,
    /// Accelerations q̈ (n) when whoever holds the state has them (an integrator after a
    /// step); `None` reads as q̈ = 0 (a state at rest). Only the sensors read them.
    pub qdd: Option<&'a DVector<f64>>,
}

impl<'a> State<'a> {
    /// The state (t, q, q̇), without accelerations.
    pub fn new(t: f64, q: &'a DVector<f64>, qd: &'a DVector<f64>) -> Self {
        State {
            t,
            q,
            qd,
            qdd: None,
        }
    }

    /// The same state with its accelerations q̈ (n).
    pub fn with_accelerations(self, qdd: &'a DVector<f64>) -> Self {
        State {
            qdd: Some(qdd),
            ..self
        }
    }
}

/// The coordinates of a compiled scene, apart from the physics: their number (the length of
/// `q0`), the number of constraint equations, the user's initial guess, and the coordinates
/// the user specified. Each formulation holds one and hands it out by
/// [`Formulation::coordinates`].
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Coordinates {
    /// Number of constraint equations m (redundant ones included).
    pub n_constraints: usize,
    /// The initial guess of the positions (n; not yet consistent).
    pub q0: DVector<f64>,
    /// The initial guess of the rates (n).
    pub qd0: DVector<f64>,
    /// Coordinates whose initial position and velocity the user specified (indices into q).
    pub specified: Vec<usize>,
}

impl Coordinates {
    /// `q0` and `qd0` (of one length n) under `n_constraints` equations, none specified.
    ///
    /// # Panics
    /// If `q0` and `qd0` differ in length.
    pub fn new(q0: DVector<f64>, qd0: DVector<f64>, n_constraints: usize) -> Self {
        assert_eq!(
            q0.len(),
            qd0.len(),
            "initial positions ({}) and rates ({}) of different lengths",
            q0.len(),
            qd0.len()
        );
        Coordinates {
            n_constraints,
            q0,
            qd0,
            specified: Vec::new(),
        }
    }
    /// n coordinates at zero under `n_constraints` equations.
    pub fn zeros(n: usize, n_constraints: usize) -> Self {
        Coordinates::new(DVector::zeros(n), DVector::zeros(n), n_constraints)
    }
    /// Number of coordinates n.
    pub fn len(&self) -> usize {
        self.q0.len()
    }
    /// True when there are no coordinates.
    pub fn is_empty(&self) -> bool {
        self.q0.is_empty()
    }
}

/// Which terms one evaluation pass must write. Terms not requested may be left stale.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Request {
    /// M and Q.
    pub dynamics: bool,
    /// K and C (only read when `dynamics` is also set).
    pub tangents: bool,
    /// Φ.
    pub constraints: bool,
    /// Φ_q and Φ_t.
    pub jacobian: bool,
    /// c = Φ̇_q q̇ + Φ̇_t.
    pub accel_term: bool,
}

impl Request {
    /// Everything.
    pub const ALL: Request = Request {
        dynamics: true,
        tangents: true,
        constraints: true,
        jacobian: true,
        accel_term: true,
    };
    /// Φ only (after a Newton update, for the multiplier update).
    pub const CONSTRAINTS: Request = Request {
        dynamics: false,
        tangents: false,
        constraints: true,
        jacobian: false,
        accel_term: false,
    };
}

/// Storage for the terms of one evaluation, sized once per scene by [`SystemTerms::new`].
#[derive(Clone, Debug)]
pub struct SystemTerms {
    /// Mass matrix M (n × n).
    pub mass: DMatrix<f64>,
    /// Generalized forces Q (n).
    pub forces: DVector<f64>,
    /// Stiffness tangent K = −∂Q/∂q (n × n).
    pub stiffness: DMatrix<f64>,
    /// Damping tangent C = −∂Q/∂q̇ (n × n).
    pub damping: DMatrix<f64>,
    /// Constraints Φ (m).
    pub phi: DVector<f64>,
    /// Constraint Jacobian Φ_q (m × n).
    pub phi_q: DMatrix<f64>,
    /// ∂Φ/∂t (m).
    pub phi_t: DVector<f64>,
    /// c = Φ̇_q q̇ + Φ̇_t (m).
    pub accel_term: DVector<f64>,
}

impl SystemTerms {
    /// Zeroed storage for `n` coordinates and `m` constraints.
    pub fn new(n: usize, m: usize) -> Self {
        SystemTerms {
            mass: DMatrix::zeros(n, n),
            forces: DVector::zeros(n),
            stiffness: DMatrix::zeros(n, n),
            damping: DMatrix::zeros(n, n),
            phi: DVector::zeros(m),
            phi_q: DMatrix::zeros(m, n),
            phi_t: DVector::zeros(m),
            accel_term: DVector::zeros(m),
        }
    }
    /// Set to zero the terms `req` asks for, before a formulation adds into them.
    pub fn clear(&mut self, req: Request) {
        // `as_mut_slice().fill` is a memset; nalgebra's element iterator is several times slower.
        if req.dynamics {
            self.mass.as_mut_slice().fill(0.0);
            self.forces.as_mut_slice().fill(0.0);
            if req.tangents {
                self.stiffness.as_mut_slice().fill(0.0);
                self.damping.as_mut_slice().fill(0.0);
            }
        }
        if req.constraints {
            self.phi.as_mut_slice().fill(0.0);
        }
        if req.jacobian {
            self.phi_q.as_mut_slice().fill(0.0);
            self.phi_t.as_mut_slice().fill(0.0);
        }
        if req.accel_term {
            self.accel_term.as_mut_slice().fill(0.0);
        }
    }
}

/// A multibody formulation the integrators can drive.
///
/// A formulation implements [`coordinates`](Formulation::coordinates) and
/// [`evaluate`](Formulation::evaluate); the questions about its coordinates are answered
/// from the former.
pub trait Formulation {
    /// Its coordinates: number, constraint count, initial guess, specified ones.
    fn coordinates(&self) -> &Coordinates;
    /// Number of coordinates n.
    fn n_coordinates(&self) -> usize {
        self.coordinates().len()
    }
    /// Number of constraint equations m (redundant ones included).
    fn n_constraints(&self) -> usize {
        self.coordinates().n_constraints
    }
    /// The user's initial guess of positions and velocities (not yet consistent).
    fn initial_guess(&self, q: &mut DVector<f64>, qd: &mut DVector<f64>) {
        let c = self.coordinates();
        q.copy_from(&c.q0);
        qd.copy_from(&c.qd0);
    }
    /// Coordinates whose initial position and velocity the user specified; they are held
    /// while the initial conditions are made consistent (docs/methods.md §5.4).
    fn specified_coordinates(&self) -> &[usize] {
        &self.coordinates().specified
    }
    /// One pass: set the requested terms of `out` at `state`. `out` comes cleared.
    fn evaluate(&mut self, state: State<'_>, req: Request, out: &mut SystemTerms);
    /// True when K and C do not depend on the state (rigid bodies, linear elasticity, linear
    /// springs): the integrator then asks for them once and keeps them, instead of clearing
    /// and rebuilding two n × n matrices at every Newton iteration.
    fn constant_tangents(&self) -> bool {
        false
    }
    /// True when the mass matrix does not depend on the state (rigid bodies in natural
    /// coordinates): with constant tangents the integrator then forms M + h/2 C + h²/4 K once.
    fn constant_mass(&self) -> bool {
        false
    }
    /// True when M, K and C are symmetric, so that the integrator may factorise its
    /// leading matrix by Cholesky (a formulation with non-symmetric tangents, e.g. the
    /// FNL1 stiffening tangent, returns false).
    fn symmetric_tangent(&self) -> bool {
        true
    }
    /// The non-zero structure of M, K, C and Φ_q, declared when the formulation is compiled
    /// ([`DeclaredPattern`](crate::DeclaredPattern)); `None` (the default) leaves the integrator on its dense or
    /// discovered-structure route.
    fn declared_pattern(&self) -> Option<crate::DeclaredPattern> {
        None
    }
    /// True when the converged positions miss the integrator's predictor by about the same
    /// amount step after step, so that the last step's miss is worth adding to the
    /// prediction (a third predictor, chosen per coordinate where it has done best). The
    /// projections of q̈ onto nonlinear constraints (a turning unit vector's length and a
    /// driven angle) move q̈ off the trapezoidal rule's q̈* by an offset that persists while
    /// the motion is steady, and the mass matrix carries it to the modal coordinates.
    fn predictor_repeats_miss(&self) -> bool {
        false
    }
    /// The coordinates that are known functions of time (a joint driven by a law) and the
    /// rows that only prescribe them, for [`DrivenEliminated`](crate::DrivenEliminated) to
    /// take out of the unknowns; `None` (the default) when there are none.
    fn driven_coordinates(&self) -> Option<crate::DrivenCoordinates> {
        None
    }
    /// (q, q̇, q̈) of each driven coordinate at time t, in the order of
    /// [`driven_coordinates`](Formulation::driven_coordinates).
    fn driven_motion(&self, _t: f64, _out: &mut [[f64; 3]]) {}
}

/// The sensors of a compiled scene, read at output instants only: outside the integrator's
/// contract, which is [`Formulation`] alone.
pub trait Observe {
    /// Names of the sensors, in output order.
    fn sensor_names(&self) -> &[String];
    /// Sensor values at `state`, one per name.
    fn sensors(&mut self, state: State<'_>, out: &mut [f64]);
    /// The pose of every body at `state` (for a viewer): `out` holds one [`BodyPose`] per
    /// body of the prepared scene, in its order; each gets its frame {r0, A} (the one
    /// [`SensorQuery::body_frame`](crate::SensorQuery::body_frame) gives the sensors) and
    /// its modal coordinates y (`modes` resized to the body's number of modes, empty when
    /// rigid). A formulation without floating frames (the ANCF cable) writes nothing.
    fn body_poses(&mut self, state: State<'_>, out: &mut [BodyPose]);
    /// The motion of every body at `state` (q̈ = 0 when the state has none): each
    /// [`BodyMotion`] gets its frame's motion (as [`SensorQuery::frame_motion`](crate::SensorQuery::frame_motion)
    /// gives it) and its modal coordinates with their rates and accelerations. Returns false,
    /// writing nothing, when the formulation does not report body motions (the default).
    fn body_motions(&mut self, _state: State<'_>, _out: &mut [BodyMotion]) -> bool {
        false
    }
}

/// A body's motion at a state: its floating frame's motion (origin, rotation, their rates
/// and accelerations, ground components) and its modal coordinates y, ẏ, ÿ (empty for a
/// rigid body), the data an inertia force M̄Ż − Q̄_v is evaluated from.
#[derive(Clone, Debug, PartialEq)]
pub struct BodyMotion {
    /// The frame's motion.
    pub frame: crate::FrameMotion,
    /// Modal coordinates y.
    pub modes: Vec<f64>,
    /// Their rates ẏ.
    pub mode_rates: Vec<f64>,
    /// Their accelerations ÿ.
    pub mode_accelerations: Vec<f64>,
}

impl Default for BodyMotion {
    /// At rest at the ground origin, unrotated, undeformed.
    fn default() -> Self {
        let zero = nalgebra::Vector3::zeros();
        BodyMotion {
            frame: crate::FrameMotion {
                origin: zero,
                rotation: nalgebra::Matrix3::identity(),
                velocity: zero,
                angular_velocity: zero,
                acceleration: zero,
                angular_acceleration: zero,
            },
            modes: Vec::new(),
            mode_rates: Vec::new(),
            mode_accelerations: Vec::new(),
        }
    }
}

/// A body's pose at a state: its floating frame's origin r0 (m, ground components), its
/// rotation A (columns: the body axes in ground components; planar: about z, z = 0) and
/// its modal coordinates y, so that a point of undeformed body position r̄_u is at
/// r0 + A (r̄_u + Φ y) (floating frame of reference, docs/methods.md §1.1).
#[derive(Clone, Debug, PartialEq)]
pub struct BodyPose {
    /// Origin r0 of the body frame (m).
    pub origin: nalgebra::Vector3<f64>,
    /// Rotation A of the body frame.
    pub rotation: nalgebra::Matrix3<f64>,
    /// Modal coordinates y (empty for a rigid body).
    pub modes: Vec<f64>,
}

impl Default for BodyPose {
    /// At the ground origin, unrotated, undeformed.
    fn default() -> Self {
        BodyPose {
            origin: nalgebra::Vector3::zeros(),
            rotation: nalgebra::Matrix3::identity(),
            modes: Vec::new(),
        }
    }
}

/// A compiled scene: the [`Formulation`] an integrator drives and the sensors ([`Observe`])
/// a simulation reads. Every type that is both is one.
pub trait CompiledScene: Formulation + Observe {}

impl<T: Formulation + Observe + ?Sized> CompiledScene for T {}

#[cfg(test)]
mod tests {
    use super::*;

    /// A formulation that only holds its coordinates.
    struct Held(Coordinates);

    impl Formulation for Held {
        fn coordinates(&self) -> &Coordinates {
            &self.0
        }
        fn evaluate(&mut self, _: State<'_>, _: Request, _: &mut SystemTerms) {}
    }

    #[test]
    fn the_questions_about_coordinates_are_answered_from_the_coordinates() {
        let q0 = DVector::from_column_slice(&[1.0, 2.0, 3.0]);
        let qd0 = DVector::from_column_slice(&[0.5, 0.0, -0.5]);
        let f = Held(Coordinates {
            specified: vec![2],
            ..Coordinates::new(q0.clone(), qd0.clone(), 2)
        });
        assert_eq!((f.n_coordinates(), f.n_constraints()), (3, 2));
        assert_eq!(f.specified_coordinates(), &[2]);
        let (mut q, mut qd) = (DVector::zeros(3), DVector::zeros(3));
        f.initial_guess(&mut q, &mut qd);
        assert_eq!((q, qd), (q0, qd0));
    }

    #[test]
    #[should_panic(expected = "different lengths")]
    fn positions_and_rates_of_different_lengths_are_refused() {
        Coordinates::new(DVector::zeros(3), DVector::zeros(2), 0);
    }
}
