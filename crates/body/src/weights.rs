//! The weights of a flexible body's inertia terms over a motion (issue 31 item 2), and the
//! cheapest [`InertiaTerms`] whose dropped terms all weigh below a threshold.
//!
//! At each sample of a motion (a pilot run of the full model) the generalised inertia force
//! of the body in the origin form {ṙ0, ω, ẏ} is evaluated for every choice of terms,
//!
//! ```text
//! F(terms) = M̄(y; terms) Ż − Q̄_v(y, Z; terms),   Ż = {r̈0, ω̇, ÿ},
//! ```
//!
//! its force and moment taken in body components (f̄ = Aᵀ f, n̄ = Aᵀ n about the frame origin
//! O). A group of terms weighs what dropping it changes, relative to the full force:
//! second order ‖F_full − F_o1‖, first order ‖F_o1 − F_o0‖, coupling ‖F_full − F_o2-nc‖,
//! gyroscopic ‖F_full − F_o2-nv‖ = ‖2G(ω̄)ẏ‖, and each candidate choice ‖F_full − F_choice‖
//! (every group it drops at once), each divided by ‖F_full‖.
//!
//! **The norm.** Translations, rotations and modal coordinates (which may be rotations of a
//! boundary DOF or mass-normalised amplitudes) have no common unit. Each block is measured
//! in the dual norm of its own kinetic energy, `‖f‖ = √(fᵀ M⁻¹ f)`: M the undeformed
//! body's rigid block (6 × 6 about O in body axes; 3 × 3 planar) for the rigid part, M_yy for
//! the modal part. `√(fᵀM⁻¹f) = √(aᵀ M a)` with `a = M⁻¹ f` the acceleration the force would
//! give the block alone: the norm does not depend on the units, on the scaling of the modes or
//! on where O is (a wrench and a twist about O transform together), and it weighs each
//! direction by how easily the body moves in it. The rigid and the modal parts are reported
//! apart: the rigid part is usually dominated by what drives the body (a spin-up hub's
//! torque), the modal part by the elastic balance, and a term that is small against the
//! driving force can still set the deformation. A weight is reported twice over the run:
//! `max_t ‖ΔF‖ / max_t ‖F_full‖` (the worst instant against the largest force, robust at an
//! instant when the body is at rest) and `√(Σ‖ΔF‖² / Σ‖F_full‖²)` (the rms).
//!
//! **The deformation weight.** Against the modal inertia force a term can look small and still
//! set the deformation, where forces that nearly cancel decide it: past the first bending
//! frequency of a spin-up beam, the centrifugal softening `Ω² M_yy y` of the second-order
//! terms and the geometric stiffening balance each other, and dropping 2 % of the modal
//! inertia force moved the tip by 41 % of its range (tests/inertia_weights.rs). So the modal
//! part is also weighed by the static deformation the dropped force would cause, in the
//! strain-energy norm: `√(ΔF_yᵀ K⁻¹ ΔF_y)` (K = K_ff, so `K⁻¹ΔF_y` is that deformation and
//! this its `√(δyᵀKδy)`) against the deformation's own `√(yᵀKy)`. A mode of frequency ω_i
//! loaded by `Ω² M_yy y` reads (Ω/ω_i)² there, however small the inertia force.
//!
//! **The choice** ([`WeightTable::choose`]) is the cheapest candidate whose dropped terms weigh
//! at most the threshold in all three (max over the run). The kernels' cost is counted by
//! their n² work (`terms.rs`): Sᵃᵇy 9n² at order 2, C(y) = C(Sᵃ) + [G_a y] 3n² at order 1
//! with couplings, G(ω̄)ẏ 3n² when the gyroscopic force is kept; ties go to the choice that
//! keeps fewer terms (less O(n) work).

use crate::{BodyState, Dim, FlexibleBody, InertiaMethod, InertiaTerms, InvalidValue};
use nalgebra::{DMatrix, DVector, Vector3};

/// One instant of a body's motion: its state (the frame's origin velocity in `state`, read by
/// [`BodyState::r0_dot`]) and the accelerations r̈0, ω̇ (ground components) and ÿ.
#[derive(Clone, Copy, Debug)]
pub struct MotionSample<'a> {
    /// Position, rotation, velocities and modal coordinates.
    pub state: BodyState<'a>,
    /// r̈0, the frame origin's acceleration (m/s², ground components).
    pub origin_acceleration: Vector3<f64>,
    /// ω̇ (rad/s², ground components).
    pub angular_acceleration: Vector3<f64>,
    /// ÿ.
    pub mode_accelerations: &'a [f64],
}

/// A group of inertia terms (module doc), weighed by what dropping it alone changes.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum TermGroup {
    /// The invariants' quadratic part in y (order 2 → 1): Ī's yᵀSᵃᵇy.
    SecondOrder,
    /// Their linear part (order 1 → 0): m̄'s S y, Ī's (Sᵃ_b + Sᵇ_a)·y, C's Sᵃᵇ y.
    FirstOrder,
    /// The rigid–elastic couplings v̄0·S ẏ + ω̄ᵀC(y) ẏ of T.
    Coupling,
    /// The workless modal gyroscopic force −2G(ω̄)ẏ.
    Gyroscopic,
}

impl TermGroup {
    /// Every group, in the table's order.
    pub const ALL: [TermGroup; 4] = [
        TermGroup::SecondOrder,
        TermGroup::FirstOrder,
        TermGroup::Coupling,
        TermGroup::Gyroscopic,
    ];

    /// Its name in tables and JSON.
    pub fn name(self) -> &'static str {
        match self {
            TermGroup::SecondOrder => "second-order",
            TermGroup::FirstOrder => "first-order",
            TermGroup::Coupling => "coupling",
            TermGroup::Gyroscopic => "gyroscopic",
        }
    }

    /// The choices whose forces differ by this group alone: (with it, without it).
    fn pair(self) -> (InertiaTerms, InertiaTerms) {
        let full = InertiaTerms::FULL;
        let order = |order| InertiaTerms { order, ..full };
        match self {
            TermGroup::SecondOrder => (full, order(1)),
            TermGroup::FirstOrder => (order(1), order(0)),
            TermGroup::Coupling => (
                full,
                InertiaTerms {
                    coupling: false,
                    ..full
                },
            ),
            TermGroup::Gyroscopic => (
                full,
                InertiaTerms {
                    velocity: false,
                    ..full
                },
            ),
        }
    }

    /// True when `terms` runs without this group.
    pub fn dropped_by(self, terms: InertiaTerms) -> bool {
        match self {
            TermGroup::SecondOrder => terms.order < 2,
            TermGroup::FirstOrder => terms.order < 1,
            TermGroup::Coupling => !terms.coupling,
            TermGroup::Gyroscopic => !(terms.coupling && terms.order >= 1 && terms.velocity),
        }
    }
}

/// The distinct choices of terms, cheapest first (module doc: n² work, then fewer terms).
/// Without couplings, or at order 0, the gyroscopic force is gone whatever `velocity` says.
pub fn candidates() -> [InertiaTerms; 8] {
    let t = |order, velocity, coupling| InertiaTerms {
        order,
        velocity,
        coupling,
    };
    [
        t(0, true, false),
        t(0, true, true),
        t(1, true, false),
        t(1, false, true),
        t(1, true, true),
        t(2, true, false),
        t(2, false, true),
        InertiaTerms::FULL,
    ]
}

/// The n² work of a choice's kernel, in units of n² multiply-adds (module doc).
pub fn kernel_work(terms: InertiaTerms) -> u32 {
    let mut w = 0;
    if terms.order >= 2 {
        w += 9;
    } else if terms.order == 1 && terms.coupling {
        w += 3;
    }
    if !TermGroup::Gyroscopic.dropped_by(terms) {
        w += 3;
    }
    w
}

/// A weight over the run, rigid and modal parts apart (module doc).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Weight {
    /// Rigid part: `max_t ‖ΔF_r‖ / max_t ‖F_r,full‖`.
    pub rigid_max: f64,
    /// Rigid part: `√(Σ‖ΔF_r‖² / Σ‖F_r,full‖²)`.
    pub rigid_rms: f64,
    /// Modal part: `max_t ‖ΔF_y‖ / max_t ‖F_y,full‖`.
    pub modal_max: f64,
    /// Modal part: `√(Σ‖ΔF_y‖² / Σ‖F_y,full‖²)`.
    pub modal_rms: f64,
    /// The static deformation the dropped modal force would cause, against the deformation:
    /// `max_t √(ΔF_yᵀK⁻¹ΔF_y) / max_t √(yᵀKy)` (module doc).
    pub deformation_max: f64,
    /// Its rms: `√(Σ ΔF_yᵀK⁻¹ΔF_y / Σ yᵀKy)`.
    pub deformation_rms: f64,
}

impl Weight {
    /// The largest of the max weights (rigid, modal, deformation): what the choice compares
    /// with a threshold.
    pub fn max(&self) -> f64 {
        self.rigid_max.max(self.modal_max).max(self.deformation_max)
    }
}

/// The weights of one body's terms over a motion.
#[derive(Clone, Debug, PartialEq)]
pub struct WeightTable {
    /// Each group's weight, in [`TermGroup::ALL`]'s order.
    pub groups: Vec<(TermGroup, Weight)>,
    /// What each candidate choice drops, weighed at once, cheapest first ([`candidates`]).
    pub candidates: Vec<(InertiaTerms, Weight)>,
    /// Samples weighed.
    pub samples: usize,
}

impl WeightTable {
    /// The cheapest candidate whose dropped terms weigh at most `threshold` (rigid, modal and
    /// deformation weights, max over the run); the full set when nothing can go. Refuses a threshold outside (0, 1),
    /// naming it.
    pub fn choose(&self, threshold: f64) -> Result<InertiaTerms, InvalidValue> {
        check_threshold(threshold)?;
        Ok(self
            .candidates
            .iter()
            .find(|(_, w)| w.max() <= threshold)
            .map_or(InertiaTerms::FULL, |(t, _)| *t))
    }
}

/// A threshold must be a fraction in (0, 1).
pub fn check_threshold(threshold: f64) -> Result<(), InvalidValue> {
    if threshold > 0.0 && threshold < 1.0 {
        Ok(())
    } else {
        Err(InvalidValue::new(
            "threshold",
            threshold,
            "must be in (0, 1): the largest weight, relative to the full inertia force, of the \
             terms that may be dropped",
        ))
    }
}

/// Running sums of one difference's norms, rigid and modal.
#[derive(Clone, Copy, Debug, Default)]
struct Sums {
    max: [f64; 3],
    squares: [f64; 3],
}

impl Sums {
    fn add(&mut self, norms: [f64; 3]) {
        for (k, v) in norms.into_iter().enumerate() {
            self.max[k] = self.max[k].max(v);
            self.squares[k] += v * v;
        }
    }

    /// This difference against the full force's sums.
    fn weight(&self, full: &Sums) -> Weight {
        let ratio = |a: f64, b: f64| if a == 0.0 { 0.0 } else { a / b };
        Weight {
            rigid_max: ratio(self.max[0], full.max[0]),
            rigid_rms: ratio(self.squares[0], full.squares[0]).sqrt(),
            modal_max: ratio(self.max[1], full.max[1]),
            modal_rms: ratio(self.squares[1], full.squares[1]).sqrt(),
            deformation_max: ratio(self.max[2], full.max[2]),
            deformation_rms: ratio(self.squares[2], full.squares[2]).sqrt(),
        }
    }
}

/// Weighs a body's terms sample by sample ([`add`](Self::add)) into a [`WeightTable`]
/// ([`table`](Self::table)), holding no sample.
#[derive(Clone, Debug)]
pub struct WeightMeter {
    body: FlexibleBody,
    /// Cholesky factors of the rigid block at y = 0 (body axes, about O) and of M_yy.
    rigid_metric: nalgebra::Cholesky<f64, nalgebra::Dyn>,
    modal_metric: nalgebra::Cholesky<f64, nalgebra::Dyn>,
    /// Cholesky factor of the modal stiffness K_ff.
    stiffness: nalgebra::Cholesky<f64, nalgebra::Dyn>,
    full: Sums,
    groups: [Sums; 4],
    candidates: [Sums; 8],
    samples: usize,
    m: DMatrix<f64>,
    q: DVector<f64>,
}

impl WeightMeter {
    /// A meter for `body` (its own choice of terms is ignored: every choice is weighed).
    /// Refused, naming `field`, for a body without modes and for one whose terms cannot be
    /// dropped (FS0).
    pub fn new(body: &FlexibleBody, field: &str) -> Result<Self, InvalidValue> {
        if body.n_modes() == 0 {
            return Err(InvalidValue::new(
                field,
                "rigid",
                "a rigid body has no modal coordinates and no inertia terms to weigh",
            ));
        }
        let mut body = body.clone();
        // Every truncation must be possible (FS0 refuses them all): probe one.
        let probe = InertiaTerms {
            order: 1,
            ..InertiaTerms::FULL
        };
        body.set_inertia_terms(probe, field)
            .map_err(|e| InvalidValue::new(field, "foreshortened (FS0)", e.reason))?;
        body.set_inertia_terms(InertiaTerms::FULL, field)?;
        let nc = body.n_coords();
        let nr = body.dim().n_rigid();
        let (mut m, mut q) = (DMatrix::zeros(nc, nc), DVector::zeros(nc));
        let zero = vec![0.0; body.n_modes()];
        let rest = BodyState {
            r0: Vector3::zeros(),
            a: nalgebra::Matrix3::identity(),
            omega: Vector3::zeros(),
            s_dot: Vector3::zeros(),
            y: &zero,
            y_dot: &zero,
        };
        body.inertia_origin(&rest, InertiaMethod::ShapeIntegrals, &mut m, &mut q);
        let factor = |block: DMatrix<f64>, what: &str| {
            block.cholesky().ok_or_else(|| {
                InvalidValue::new(
                    field,
                    what,
                    "the block's mass matrix is not positive definite",
                )
            })
        };
        let rigid_metric = factor(m.view((0, 0), (nr, nr)).into_owned(), "rigid mass")?;
        let modal_metric = factor(body.m_yy(), "modal mass M_yy")?;
        let stiffness = factor(body.k_ff().clone(), "modal stiffness K_ff")?;
        Ok(Self {
            body,
            rigid_metric,
            modal_metric,
            stiffness,
            full: Sums::default(),
            groups: [Sums::default(); 4],
            candidates: [Sums::default(); 8],
            samples: 0,
            m,
            q,
        })
    }

    /// F(terms) at `s` with the force and moment in body components (module doc).
    fn force(
        &mut self,
        s: &MotionSample<'_>,
        terms: InertiaTerms,
        z_dot: &DVector<f64>,
    ) -> DVector<f64> {
        self.body
            .set_inertia_terms(terms, "terms")
            .expect("checked when the meter was built");
        let st = &s.state;
        self.body
            .inertia_origin(st, InertiaMethod::ShapeIntegrals, &mut self.m, &mut self.q);
        let mut f = &self.m * z_dot - &self.q;
        let at = st.a.transpose();
        match self.body.dim() {
            Dim::Spatial => {
                let force = at * Vector3::new(f[0], f[1], f[2]);
                let moment = at * Vector3::new(f[3], f[4], f[5]);
                f.rows_mut(0, 3).copy_from(&force);
                f.rows_mut(3, 3).copy_from(&moment);
            }
            Dim::Planar => {
                let force = at * Vector3::new(f[0], f[1], 0.0);
                f[0] = force.x;
                f[1] = force.y;
            }
        }
        f
    }

    /// The rigid and modal dual norms of a force and its modal part's in K (module doc).
    fn norms(&self, f: &DVector<f64>) -> [f64; 3] {
        let nr = self.body.dim().n_rigid();
        let dual = |metric: &nalgebra::Cholesky<f64, nalgebra::Dyn>, part: DVector<f64>| {
            part.dot(&metric.solve(&part)).max(0.0).sqrt()
        };
        let n = f.len() - nr;
        let modal = f.rows(nr, n).into_owned();
        [
            dual(&self.rigid_metric, f.rows(0, nr).into_owned()),
            dual(&self.modal_metric, modal.clone()),
            dual(&self.stiffness, modal),
        ]
    }

    /// Weigh one sample. Panics if its sizes do not match the body (as the kernels do).
    pub fn add(&mut self, s: &MotionSample<'_>) {
        let nr = self.body.dim().n_rigid();
        let mut z_dot = DVector::zeros(self.body.n_coords());
        match self.body.dim() {
            Dim::Spatial => {
                z_dot.rows_mut(0, 3).copy_from(&s.origin_acceleration);
                z_dot.rows_mut(3, 3).copy_from(&s.angular_acceleration);
            }
            Dim::Planar => {
                z_dot[0] = s.origin_acceleration.x;
                z_dot[1] = s.origin_acceleration.y;
                z_dot[2] = s.angular_acceleration.z;
            }
        }
        z_dot
            .rows_mut(nr, self.body.n_modes())
            .copy_from_slice(s.mode_accelerations);
        let forces: Vec<DVector<f64>> = candidates()
            .iter()
            .map(|&t| self.force(s, t, &z_dot))
            .collect();
        let of = |t: InertiaTerms| {
            let k = candidates()
                .iter()
                .position(|&c| c == t)
                .expect("a candidate");
            &forces[k]
        };
        let full = of(InertiaTerms::FULL);
        let [rigid, modal, _] = self.norms(full);
        let y = DVector::from_column_slice(s.state.y);
        let strain = y.dot(&(self.body.k_ff() * &y)).max(0.0).sqrt();
        self.full.add([rigid, modal, strain]);
        for (k, g) in TermGroup::ALL.into_iter().enumerate() {
            let (with, without) = g.pair();
            let d = self.norms(&(of(with) - of(without)));
            self.groups[k].add(d);
        }
        for (k, f) in forces.iter().enumerate() {
            let d = self.norms(&(full - f));
            self.candidates[k].add(d);
        }
        self.samples += 1;
        self.body
            .set_inertia_terms(InertiaTerms::FULL, "terms")
            .expect("the full set");
    }

    /// The weights of the samples added so far.
    pub fn table(&self) -> WeightTable {
        WeightTable {
            groups: TermGroup::ALL
                .into_iter()
                .zip(&self.groups)
                .map(|(g, s)| (g, s.weight(&self.full)))
                .collect(),
            candidates: candidates()
                .into_iter()
                .zip(&self.candidates)
                .map(|(t, s)| (t, s.weight(&self.full)))
                .collect(),
            samples: self.samples,
        }
    }
}

/// The weights of `body`'s terms over `samples` ([`WeightMeter`]).
pub fn weigh<'a>(
    body: &FlexibleBody,
    samples: impl IntoIterator<Item = MotionSample<'a>>,
    field: &str,
) -> Result<WeightTable, InvalidValue> {
    let mut meter = WeightMeter::new(body, field)?;
    for s in samples {
        meter.add(&s);
    }
    Ok(meter.table())
}
