//! The body kernels of §4.5 step 4: a body's M̄_k and P_k = Q̄_k − M̄_k {D_k; 0} in the s form
//! (docs/methods.md §2.4, §2.6, §4.1), by a kernel chosen when the scene is compiled.
//!
//! A **rigid body** (no modal coordinates) has a closed form on fixed-size blocks from its
//! mass m, first moment m̄ = m c̄ about its frame origin and inertia tensor Ī_O about that
//! origin (body components; `FlexibleBody::{mass, first_moment, inertia_about_origin}`, the
//! mass properties its inertia routes start from), with c = A m̄, the first moment about the
//! global origin g = m r0 + c, the origin's velocity ṙ0 = ṡ + ω × r0 and gravity γ:
//!
//! ```text
//! M̄ = [ m I   −g̃ ]      J = A Ī_O Aᵀ + m (|r0|² I − r0 r0ᵀ) + 2 (r0·c) I − r0 cᵀ − c r0ᵀ
//!     [ g̃     J  ]
//! Q̄_t = m (γ − ω × ṙ0) − ω × (ω × c)
//! Q̄_r = r0 × Q̄_t + c × (γ − ω × ṙ0) − ω × (A Ī_O Aᵀ ω)
//! P = Q̄ − M̄ {D_s; D_ω} = {Q̄_t − m D_s + g × D_ω;  Q̄_r − g × D_s − J D_ω}
//! ```
//!
//! which is §2.4 steps 1–3 at n = 0 (Q̄_v,body = −{ω̄~ω̄~ m̄; ω̄~ Ī_O ω̄}, rotated, shifted to s
//! with ā = ω̄ × v̄0) plus the s-form gravity {m γ; g × γ} of §2.6. A planar body keeps the
//! x, y, θz rows (§0): g = (g_x, g_y), J = I_zz + m |r0|² + 2 r0·c, Q̄ = {m (γ − ω E ṙ0) +
//! ω² c; (r0 × Q̄_t + c × (γ − ω E ṙ0))_z}, E the rotation by +90°. Both are written straight
//! into the 6-layout blocks the subtree accumulation reads.
//!
//! A **flexible body** runs `flexmbd-body`'s inertia routes ([`flexmbd_body::InertiaMethod`])
//! on its dense M̄_k, Q̄_k, with gravity and the elastic forces; `dynamics.rs` then takes its
//! rigid block and modal rows apart.

use flexmbd_body::{BodyState, FlexibleBody, InertiaMethod, RelativeBlocks};
use flexmbd_core::skew;
use nalgebra::{DMatrix, DVector, Matrix3, Matrix6, Vector2, Vector3, Vector6};

/// A rigid body's mass properties in its frame (body components), fixed at compile.
#[derive(Clone, Debug)]
pub(crate) struct RigidSpatial {
    /// m (kg).
    mass: f64,
    /// m̄ = m c̄ about the frame origin (kg·m).
    first_moment: Vector3<f64>,
    /// Ī_O about the frame origin, body axes (kg·m²).
    inertia: Matrix3<f64>,
}

/// A planar rigid body's mass properties in its frame: the in-plane entries of
/// [`RigidSpatial`].
#[derive(Clone, Debug)]
pub(crate) struct RigidPlanar {
    /// m (kg).
    mass: f64,
    /// (m̄_x, m̄_y) about the frame origin (kg·m).
    first_moment: Vector2<f64>,
    /// I_zz about the frame origin (kg·m²).
    inertia: f64,
}

/// A flexible body: its terms by block for the dynamics pass (a fixed 6 × 6 rigid block,
/// the coupling columns and the modal rows), and dense storage for the inspectors.
#[derive(Clone, Debug)]
pub(crate) struct Flexible {
    pub(crate) body: FlexibleBody,
    /// M̄_k, Q̄_k in the s form by block (Q̄ with gravity and the elastic forces), from
    /// [`evaluate`](Self::evaluate).
    pub(crate) blocks: RelativeBlocks,
    /// Dense M̄_k, Q̄_k (rigid_size + n_modes) for the energy and the initial velocity fit.
    pub(crate) m_bar: DMatrix<f64>,
    pub(crate) q_bar: DVector<f64>,
    /// Scratch: the generalized gravity forces.
    gravity_forces: Vec<f64>,
    /// Scratch: the elastic forces on the modes (n_modes).
    elastic_forces: Vec<f64>,
}

/// The kernel of one body, chosen when the scene is compiled.
#[derive(Clone, Debug)]
pub(crate) enum BodyKernel {
    RigidSpatial(RigidSpatial),
    RigidPlanar(RigidPlanar),
    Flexible(Box<Flexible>),
}

/// Where a body's frame is and how it moves, from the kinematic pass (global components).
#[derive(Clone, Copy, Debug)]
pub(crate) struct FrameMotion {
    /// Origin r0 and rotation A.
    pub(crate) r0: Vector3<f64>,
    pub(crate) a: Matrix3<f64>,
    /// Z^r = {ṡ; ω} and the velocity-product acceleration {D_s; D_ω}.
    pub(crate) velocity: Vector6<f64>,
    pub(crate) bias: Vector6<f64>,
}

/// A [`FrameMotion`]'s r0, A, Z^r and D by reference.
pub(crate) type FrameParts<'a> = (
    &'a Vector3<f64>,
    &'a Matrix3<f64>,
    &'a Vector6<f64>,
    &'a Vector6<f64>,
);

impl BodyKernel {
    /// The kernel of `body` with `n_modes` coordinates (0: rigid) for a scene whose rigid
    /// velocity set has `rigid_size` entries (3 planar, 6 spatial).
    pub(crate) fn new(body: FlexibleBody, n_modes: usize, rigid_size: usize) -> BodyKernel {
        if n_modes > 0 {
            let nc = rigid_size + n_modes;
            return BodyKernel::Flexible(Box::new(Flexible {
                blocks: body.relative_blocks(),
                body,
                m_bar: DMatrix::zeros(nc, nc),
                q_bar: DVector::zeros(nc),
                gravity_forces: vec![0.0; nc],
                elastic_forces: vec![0.0; n_modes],
            }));
        }
        let (mass, first_moment, inertia) = (
            body.mass(),
            body.first_moment(),
            body.inertia_about_origin(),
        );
        if rigid_size == 3 {
            BodyKernel::RigidPlanar(RigidPlanar {
                mass,
                first_moment: first_moment.xy(),
                inertia: inertia[(2, 2)],
            })
        } else {
            BodyKernel::RigidSpatial(RigidSpatial {
                mass,
                first_moment,
                inertia,
            })
        }
    }

    /// The flexible body, if this is one.
    pub(crate) fn flexible(&self) -> Option<&Flexible> {
        match self {
            BodyKernel::Flexible(f) => Some(f),
            _ => None,
        }
    }

    /// Mass m and first moment about the frame origin m̄(y) in body components.
    pub(crate) fn mass_and_first_moment(&self, y: &[f64]) -> (f64, Vector3<f64>) {
        match self {
            BodyKernel::RigidSpatial(r) => (r.mass, r.first_moment),
            BodyKernel::RigidPlanar(r) => (
                r.mass,
                Vector3::new(r.first_moment.x, r.first_moment.y, 0.0),
            ),
            BodyKernel::Flexible(f) => (f.body.mass(), f.body.first_moment_at(y)),
        }
    }
}

impl RigidSpatial {
    /// M̄ (6 × 6) and P = Q̄ − M̄ {D_s; D_ω} (module doc) at the frame's motion, gravity γ.
    #[inline]
    pub(crate) fn terms(
        &self,
        frame: &FrameMotion,
        gravity: &Vector3<f64>,
        mass: &mut Matrix6<f64>,
        p: &mut Vector6<f64>,
    ) {
        let (q, m) = self.mass_and_forces(frame, gravity);
        let (d_s, d_w) = (
            frame.bias.fixed_rows::<3>(0).into_owned(),
            frame.bias.fixed_rows::<3>(3).into_owned(),
        );
        let (g, j) = (m.moment, m.inertia);
        let pt = q.fixed_rows::<3>(0) - self.mass * d_s + g.cross(&d_w);
        let pr = q.fixed_rows::<3>(3) - g.cross(&d_s) - j * d_w;
        p.fixed_rows_mut::<3>(0).copy_from(&pt);
        p.fixed_rows_mut::<3>(3).copy_from(&pr);
        let gt = skew(&g);
        mass.fixed_view_mut::<3, 3>(0, 0)
            .copy_from(&(Matrix3::identity() * self.mass));
        mass.fixed_view_mut::<3, 3>(0, 3).copy_from(&(-gt));
        mass.fixed_view_mut::<3, 3>(3, 0).copy_from(&gt);
        mass.fixed_view_mut::<3, 3>(3, 3).copy_from(&j);
    }

    /// Q̄ = {Q̄_t; Q̄_r} (inertia and gravity) and the mass blocks g, J (module doc).
    #[inline(always)]
    fn mass_and_forces(
        &self,
        frame: &FrameMotion,
        gravity: &Vector3<f64>,
    ) -> (Vector6<f64>, SpatialMass) {
        let (r0, a) = (&frame.r0, &frame.a);
        let s_dot = frame.velocity.fixed_rows::<3>(0).into_owned();
        let w = frame.velocity.fixed_rows::<3>(3).into_owned();
        let c = a * self.first_moment;
        let g = self.mass * r0 + c;
        let io = a * self.inertia * a.transpose();
        let r0_dot = s_dot + w.cross(r0);
        let accel = gravity - w.cross(&r0_dot);
        let qt = self.mass * accel - w.cross(&w.cross(&c));
        let qr = r0.cross(&qt) + c.cross(&accel) - w.cross(&(io * w));
        let rc = r0.dot(&c);
        let j = io + Matrix3::identity() * (self.mass * r0.norm_squared() + 2.0 * rc)
            - self.mass * r0 * r0.transpose()
            - r0 * c.transpose()
            - c * r0.transpose();
        let mut q = Vector6::zeros();
        q.fixed_rows_mut::<3>(0).copy_from(&qt);
        q.fixed_rows_mut::<3>(3).copy_from(&qr);
        (
            q,
            SpatialMass {
                moment: g,
                inertia: j,
            },
        )
    }
}

/// The position-dependent blocks of a spatial rigid M̄: g and J about the global origin.
struct SpatialMass {
    moment: Vector3<f64>,
    inertia: Matrix3<f64>,
}

impl RigidPlanar {
    /// M̄ and P = Q̄ − M̄ {D_x; D_y; D_θ} (module doc) in the x, y, θz entries of the 6-layout
    /// (0, 1, 5; the others are not written), gravity γ (γ_z unused).
    #[inline]
    pub(crate) fn terms(
        &self,
        frame: &FrameMotion,
        gravity: &Vector3<f64>,
        mass: &mut Matrix6<f64>,
        p: &mut Vector6<f64>,
    ) {
        let motion = (&frame.r0, &frame.a, &frame.velocity, &frame.bias);
        self.terms_at(motion, gravity, mass, p);
    }

    /// [`terms`](Self::terms) at the frame's r0, A, Z^r and D given by reference: only the
    /// planar entries are read (the pass reads them straight from its arrays, without copying
    /// the whole motion).
    #[inline(always)]
    pub(crate) fn terms_at(
        &self,
        (r0, a, velocity, bias): FrameParts<'_>,
        gravity: &Vector3<f64>,
        mass: &mut Matrix6<f64>,
        p: &mut Vector6<f64>,
    ) {
        let (q, g, j) = self.mass_and_forces((r0, a, velocity), gravity);
        let m = self.mass;
        let (dx, dy, dth) = (bias[0], bias[1], bias[5]);
        // M̄ = [[m, 0, −g_y], [0, m, g_x], [−g_y, g_x, J]].
        p[0] = q[0] - m * dx + g.y * dth;
        p[1] = q[1] - m * dy - g.x * dth;
        p[5] = q[2] + g.y * dx - g.x * dy - j * dth;
        mass[(0, 0)] = m;
        mass[(1, 1)] = m;
        mass[(0, 5)] = -g.y;
        mass[(5, 0)] = -g.y;
        mass[(1, 5)] = g.x;
        mass[(5, 1)] = g.x;
        mass[(5, 5)] = j;
    }

    /// Q̄ = {Q̄_x; Q̄_y; Q̄_θ} (inertia and gravity), g = m r0 + c and J (module doc).
    #[inline(always)]
    fn mass_and_forces(
        &self,
        (r0, a, velocity): (&Vector3<f64>, &Matrix3<f64>, &Vector6<f64>),
        gravity: &Vector3<f64>,
    ) -> ([f64; 3], Vector2<f64>, f64) {
        let a = a.fixed_view::<2, 2>(0, 0).into_owned();
        let r0 = r0.xy();
        let w = velocity[5];
        let s_dot = Vector2::new(velocity[0], velocity[1]);
        let c = a * self.first_moment;
        let g = self.mass * r0 + c;
        let r0_dot = s_dot + w * Vector2::new(-r0.y, r0.x);
        let accel = gravity.xy() - w * Vector2::new(-r0_dot.y, r0_dot.x);
        let qt = self.mass * accel + (w * w) * c;
        let cross = |u: Vector2<f64>, v: Vector2<f64>| u.x * v.y - u.y * v.x;
        let qr = cross(r0, qt) + cross(c, accel);
        let j = self.inertia + self.mass * r0.norm_squared() + 2.0 * r0.dot(&c);
        ([qt.x, qt.y, qr], g, j)
    }
}

impl Flexible {
    /// M̄_k and Q̄_k (inertia by `method`, gravity γ, elastic forces) into `blocks`;
    /// `rigid_entries` are the scene's rigid entries of the 6-layout (x, y, θz in 2D).
    pub(crate) fn evaluate(
        &mut self,
        state: &BodyState<'_>,
        method: InertiaMethod,
        gravity: &Vector3<f64>,
        rigid_entries: &[usize],
    ) {
        let rigid_size = rigid_entries.len();
        self.body.inertia_blocks(state, method, &mut self.blocks);
        self.body
            .gravity_forces(state, gravity, &mut self.gravity_forces);
        let (rigid_gravity, modal_gravity) = self.gravity_forces.split_at(rigid_size);
        for (&e, gv) in rigid_entries.iter().zip(rigid_gravity) {
            self.blocks.rigid_force[e] += gv;
        }
        for (q, gv) in self.blocks.modal_force.iter_mut().zip(modal_gravity) {
            *q += gv;
        }
        self.body
            .elastic_forces(state.y, state.y_dot, &mut self.elastic_forces);
        for (q, f) in self.blocks.modal_force.iter_mut().zip(&self.elastic_forces) {
            *q += f;
        }
    }

    /// The dense M̄_k and Q̄_k of the last [`evaluate`](Self::evaluate) in the body's layout
    /// (allocates; for the inspectors).
    pub(crate) fn dense_terms(&self, rigid_entries: &[usize]) -> (DMatrix<f64>, DVector<f64>) {
        let (rs, b) = (rigid_entries.len(), &self.blocks);
        let n = b.modal_force.len();
        let (mut m, mut q) = (DMatrix::zeros(rs + n, rs + n), DVector::zeros(rs + n));
        for (r, &er) in rigid_entries.iter().enumerate() {
            q[r] = b.rigid_force[er];
            for (c, &ec) in rigid_entries.iter().enumerate() {
                m[(r, c)] = b.rigid[(er, ec)];
            }
            for (j, u) in b.coupling.iter().enumerate() {
                m[(r, rs + j)] = u[er];
                m[(rs + j, r)] = u[er];
            }
        }
        for i in 0..n {
            q[rs + i] = b.modal_force[i];
            for j in 0..n {
                m[(rs + i, rs + j)] = b.modal_mass[i * n + j];
            }
        }
        (m, q)
    }
}

/// A rigid body's M̄ and Q̄ (with gravity) in its own layout (3 or 6 entries), dense, for the
/// inspectors and the initial velocity fit (allocates; not on the per-step path).
pub(crate) fn rigid_dense_terms(
    kernel: &BodyKernel,
    frame: &FrameMotion,
    gravity: &Vector3<f64>,
) -> Option<(DMatrix<f64>, DVector<f64>)> {
    let zero_bias = FrameMotion {
        bias: Vector6::zeros(),
        ..*frame
    };
    let (mut mass, mut p) = (Matrix6::zeros(), Vector6::zeros());
    let entries: &[usize] = match kernel {
        BodyKernel::RigidSpatial(r) => {
            r.terms(&zero_bias, gravity, &mut mass, &mut p);
            &[0, 1, 2, 3, 4, 5]
        }
        BodyKernel::RigidPlanar(r) => {
            r.terms(&zero_bias, gravity, &mut mass, &mut p);
            &[0, 1, 5]
        }
        BodyKernel::Flexible(_) => return None,
    };
    let n = entries.len();
    Some((
        DMatrix::from_fn(n, n, |i, j| mass[(entries[i], entries[j])]),
        DVector::from_fn(n, |i, _| p[entries[i]]),
    ))
}

#[cfg(test)]
mod tests {
    use super::*;
    use flexmbd_body::ReducedBody;
    use flexmbd_core::Dim;
    use nalgebra::Rotation3;

    /// A frame at a general pose and motion.
    fn frame(planar: bool) -> FrameMotion {
        let (a, r0, velocity, bias) = if planar {
            (
                *Rotation3::from_axis_angle(&Vector3::z_axis(), 0.7).matrix(),
                Vector3::new(0.4, -1.3, 0.0),
                Vector6::new(0.8, -0.3, 0.0, 0.0, 0.0, 2.1),
                Vector6::new(-1.5, 0.6, 0.0, 0.0, 0.0, 3.2),
            )
        } else {
            (
                *Rotation3::from_euler_angles(0.3, -0.9, 1.7).matrix(),
                Vector3::new(0.4, -1.3, 0.8),
                Vector6::new(0.8, -0.3, 1.1, 2.1, -0.7, 1.4),
                Vector6::new(-1.5, 0.6, 0.2, 3.2, -0.4, 0.9),
            )
        };
        FrameMotion {
            r0,
            a,
            velocity,
            bias,
        }
    }

    /// The closed form against `flexmbd-body`'s routes on the rigid body's mass cloud (shape
    /// integrals and B-matrix projection, plus the s-form gravity), and P against Q̄ − M̄ D.
    fn check(dim: Dim) {
        let planar = dim == Dim::Planar;
        let inertia = Matrix3::new(2.0, 0.3, -0.1, 0.3, 1.5, 0.2, -0.1, 0.2, 1.1);
        let com = if planar {
            Vector3::new(0.3, -0.2, 0.0)
        } else {
            Vector3::new(0.3, -0.2, 0.5)
        };
        let reduced = ReducedBody::rigid(dim, 3.5, com, inertia).unwrap();
        let mut body = FlexibleBody::new(&reduced).unwrap();
        let kernel = BodyKernel::new(body.clone(), 0, dim.n_rigid());
        let gravity = Vector3::new(0.5, -9.81, if planar { 0.0 } else { 1.2 });
        let fr = frame(planar);
        let entries: &[usize] = if planar {
            &[0, 1, 5]
        } else {
            &[0, 1, 2, 3, 4, 5]
        };
        let (mass, q) = rigid_dense_terms(&kernel, &fr, &gravity).unwrap();
        let state = BodyState {
            r0: fr.r0,
            a: fr.a,
            omega: fr.velocity.fixed_rows::<3>(3).into_owned(),
            s_dot: fr.velocity.fixed_rows::<3>(0).into_owned(),
            y: &[],
            y_dot: &[],
        };
        let n = entries.len();
        for method in [InertiaMethod::ShapeIntegrals, InertiaMethod::BMatrix] {
            let (mut m_ref, mut q_ref) = (DMatrix::zeros(n, n), DVector::zeros(n));
            body.inertia(&state, method, &mut m_ref, &mut q_ref);
            let mut gf = vec![0.0; n];
            body.gravity_forces(&state, &gravity, &mut gf);
            for (qv, g) in q_ref.iter_mut().zip(&gf) {
                *qv += g;
            }
            let dm = (&mass - &m_ref).abs().max() / m_ref.abs().max();
            let dq = (&q - &q_ref).abs().max() / q_ref.abs().max();
            assert!(
                dm < 1e-14,
                "{dim:?} {method:?}: M̄ differs by {dm:e} of its largest"
            );
            assert!(
                dq < 1e-14,
                "{dim:?} {method:?}: Q̄ differs by {dq:e} of its largest"
            );
        }
        let (mut m6, mut p6) = (Matrix6::zeros(), Vector6::zeros());
        match &kernel {
            BodyKernel::RigidSpatial(r) => r.terms(&fr, &gravity, &mut m6, &mut p6),
            BodyKernel::RigidPlanar(r) => r.terms(&fr, &gravity, &mut m6, &mut p6),
            BodyKernel::Flexible(_) => unreachable!(),
        }
        let d = DVector::from_fn(n, |i, _| fr.bias[entries[i]]);
        let p_ref = &q - &mass * d;
        for (i, &e) in entries.iter().enumerate() {
            let dp = (p6[e] - p_ref[i]).abs() / p_ref.abs().max();
            assert!(
                dp < 1e-14,
                "{dim:?}: P[{e}] differs by {dp:e} of the largest"
            );
        }
    }

    #[test]
    fn spatial_rigid_kernel_matches_both_inertia_routes() {
        check(Dim::Spatial);
    }

    #[test]
    fn planar_rigid_kernel_matches_both_inertia_routes() {
        check(Dim::Planar);
    }
}
