//! The **link**: a spring and a damper of nonlinear laws ([`crate::laws`]) between markers P1
//! (body1) and P2 (body2), tension positive: F = spring(l) + damper(l̇), Q = −F ∂l/∂q.
//!
//! - **Along the line of the markers** (`axis: None`): l = |d|, d = r_P2 − r_P1, n = d/l,
//!   l̇ = n·(ṙ_P2 − ṙ_P1). As the spring–damper: Q = −F Jᵀn,
//!   K ≈ Jᵀ(F_s'(l) nnᵀ + F/l (I − nnᵀ))J, C ≈ F_d'(l̇) Jᵀnnᵀ J.
//! - **Along a body1-fixed axis a** (`axis: Some(a)`, body1 components, normalised):
//!   l = a·d with a turning with body1. The direction is written as the difference of two
//!   points of body1, a = r_A − r_P1, A = P1 + a being an auxiliary marker that
//!   [`PreparedScene::new`](crate::PreparedScene::new) adds to body1 (body1 rigid or the
//!   ground: on a flexible body the axis would turn with the deformation). Every term then
//!   goes through marker Jacobians: ∂l/∂q = a·(J2 − J1) + d·(J_A − J1), so
//!   Q = −F [a·(J2 − J1) + d·(J_A − J1)] and l̇ = a·(ṙ_P2 − ṙ_P1) + d·(ṙ_A − ṙ_P1);
//!   tangents K ≈ F_s'(l) g gᵀ, C ≈ F_d'(l̇) g gᵀ with g = ∂l/∂q.
//!
//! **Why the axis link is S9's leaf element** (docs/scenes.md §2.4, S9 user_cons_hJ.c,
//! user_LinkForces.c): S9 joins U to a chassis point E that slides along the chassis y axis,
//! held by a user constraint at U's chassis y, so the force −F e on U and +F e on E acts
//! along the chassis axis e = a through U. The sliding E is massless: all it transmits to the
//! chassis is that force, whose line of action passes through U. Our link applies −F a at U
//! and, through the same virtual work, the force F a plus the moment of it about the
//! chassis — it is the force +F a with its line of action through U, not through P1: the
//! term d·(J_A − J1) is the virtual work of the chassis's rotation δθ × a, which equals the
//! moment (d × F a)·δθ of moving the force from P1 to U. And S9's length s = z(E) − z(U)
//! along the chassis z axis is a·(r_P1 − r_U) with P1 any chassis point at E's height, for
//! a = (0, 0, −1) and r_P2 = r_U: l = a·(r_U − r_P1) = z_E − z_U. Where E slides to does not
//! change l, so P1 only fixes E's height.
//!
//! The potential energy of the spring is ∫ spring(l) dl from the length at the start
//! ([`crate::laws::Law::integral`], exact); the damper is not conservative.

use flexmbd_core::{ElementReading, MarkerKinematics, SystemTerms};
use nalgebra::{DVector, Vector3};

use super::{Scratch, add_line_tangents, line_columns, merge_coordinates};
use crate::error::ModelError;
use crate::inputs::InputSlots;
use crate::laws::Law;
use crate::scene::{Force, GROUND, Marker, Scene, V3};

/// A compiled link, `M` being the formulation's marker handle.
#[derive(Clone, Debug)]
pub struct Link<M> {
    /// Marker P1 (body1).
    pub first: M,
    /// Marker P2 (body2).
    pub second: M,
    /// The auxiliary marker P1 + a of a link along a body1-fixed axis.
    pub axis: Option<M>,
    /// Tension of the length (N).
    pub spring: Law,
    /// Tension of the rate (N).
    pub damper: Law,
    /// The length at the start (m): the spring's energy is counted from it.
    pub start_length: f64,
    /// The `Scale` input that multiplies the spring's and the damper's tension (and their
    /// slopes), if any ([`crate::inputs`]).
    pub scale: Option<InputSlots>,
}

/// The link's geometry at (q, q̇): d, the unit direction (n or a), l and l̇.
struct Geometry {
    d: Vector3<f64>,
    direction: Vector3<f64>,
    length: f64,
    rate: f64,
}

impl<M> Link<M> {
    /// Compile `force` (a `Link`) over the handles (P1, P2, A).
    pub(super) fn new<K>(
        force: &Force,
        origin: &str,
        (first, second, axis): (M, M, Option<M>),
        kinematics: &K,
        q0: &DVector<f64>,
        qd0: &DVector<f64>,
    ) -> Result<Self, ModelError>
    where
        K: MarkerKinematics<Marker = M>,
    {
        let Force::Link { spring, damper, .. } = force else {
            unreachable!("Link::new is given links")
        };
        let (r1, _) = kinematics.marker_state(&first, q0, qd0);
        let (r2, _) = kinematics.marker_state(&second, q0, qd0);
        if axis.is_none() {
            // Along the line: its markers may not coincide (no direction).
            force.spring_free_length(origin, &r1, &r2)?;
        }
        let mut link = Link {
            first,
            second,
            axis,
            spring: spring.clone(),
            damper: damper.clone(),
            start_length: 0.0,
            scale: None,
        };
        link.start_length = link.geometry(kinematics, q0, qd0).length;
        Ok(link)
    }

    /// The spring's (tension, slope) at length l, scaled by the input's s_k if any.
    fn spring_at(&self, l: f64) -> (f64, f64) {
        let (f, k) = self.spring.eval(l);
        match &self.scale {
            None => (f, k),
            Some(s) => (f * s.get(0), k * s.get(0)),
        }
    }

    /// The damper's (tension, slope) at rate l̇, scaled by the input's s_c if any.
    fn damper_at(&self, rate: f64) -> (f64, f64) {
        let (f, c) = self.damper.eval(rate);
        match &self.scale {
            None => (f, c),
            Some(s) => (f * s.get(1), c * s.get(1)),
        }
    }

    fn geometry<K>(&self, kinematics: &K, q: &DVector<f64>, qd: &DVector<f64>) -> Geometry
    where
        K: MarkerKinematics<Marker = M>,
    {
        let (r1, v1) = kinematics.marker_state(&self.first, q, qd);
        let (r2, v2) = kinematics.marker_state(&self.second, q, qd);
        let d = r2 - r1;
        match &self.axis {
            None => {
                let length = d.norm();
                let n = d / length;
                Geometry {
                    d,
                    direction: n,
                    length,
                    rate: n.dot(&(v2 - v1)),
                }
            }
            Some(aux) => {
                let (ra, va) = kinematics.marker_state(aux, q, qd);
                let a = ra - r1;
                Geometry {
                    d,
                    direction: a,
                    length: a.dot(&d),
                    rate: a.dot(&(v2 - v1)) + d.dot(&(va - v1)),
                }
            }
        }
    }

    /// Q (and K, C) of the link at (q, q̇).
    pub(super) fn add_forces<K>(
        &self,
        kinematics: &mut K,
        q: &DVector<f64>,
        qd: &DVector<f64>,
        tangents: bool,
        scratch: &mut Scratch,
        out: &mut SystemTerms,
    ) where
        K: MarkerKinematics<Marker = M>,
    {
        let g = self.geometry(kinematics, q, qd);
        let (fs, ks) = self.spring_at(g.length);
        let (fd, cd) = self.damper_at(g.rate);
        let f = fs + fd;
        match &self.axis {
            None => {
                let columns = &mut scratch.columns;
                line_columns(kinematics, &self.first, &self.second, q, columns);
                for &(i, c) in columns.iter() {
                    out.forces[i] -= f * g.direction.dot(&c);
                }
                if tangents {
                    let merged = &mut scratch.merged_columns;
                    merge_coordinates(columns, &mut scratch.slot, merged);
                    add_line_tangents(&g.direction, ks, f, g.length, cd, merged, out);
                }
            }
            Some(aux) => {
                let gradient = &mut scratch.gradient;
                gradient.clear();
                let (a, d) = (g.direction, g.d);
                kinematics
                    .marker_jacobian(&self.second, q, &mut |i, c| gradient.push((i, a.dot(&c))));
                kinematics.marker_jacobian(&self.first, q, &mut |i, c| {
                    gradient.push((i, -(a + d).dot(&c)))
                });
                kinematics.marker_jacobian(aux, q, &mut |i, c| gradient.push((i, d.dot(&c))));
                for &(i, gi) in gradient.iter() {
                    out.forces[i] -= f * gi;
                }
                if tangents {
                    let merged = &mut scratch.merged_gradient;
                    merge_coordinates(gradient, &mut scratch.slot, merged);
                    for &(i, gi) in merged.iter() {
                        for &(j, gj) in merged.iter() {
                            out.stiffness[(j, i)] += ks * (gj * gi);
                            out.damping[(j, i)] += cd * (gj * gi);
                        }
                    }
                }
            }
        }
    }

    /// Tension and length at (q, q̇).
    pub(super) fn reading<K>(
        &self,
        kinematics: &K,
        q: &DVector<f64>,
        qd: &DVector<f64>,
    ) -> ElementReading
    where
        K: MarkerKinematics<Marker = M>,
    {
        let g = self.geometry(kinematics, q, qd);
        ElementReading {
            force: self.spring_at(g.length).0 + self.damper_at(g.rate).0,
            length: g.length,
        }
    }

    /// ∫ spring dl from the start length (J).
    pub(super) fn potential_energy<K>(
        &self,
        kinematics: &K,
        q: &DVector<f64>,
        qd: &DVector<f64>,
    ) -> f64
    where
        K: MarkerKinematics<Marker = M>,
    {
        let l = self.geometry(kinematics, q, qd).length;
        let energy = self.spring.integral(self.start_length, l);
        match &self.scale {
            None => energy,
            Some(s) => energy * s.get(0),
        }
    }
}

/// The prefix of the auxiliary axis markers' names.
const AXIS_MARKER: &str = "__axis_of_";

/// Add to body1 of every link along a body-fixed axis a the auxiliary marker P1 + a/|a|
/// (body1 components; ground components for the ground), and name it per force element
/// ((body, marker) or `None`). Other scenes are returned unchanged.
pub(crate) fn add_axis_markers(mut scene: Scene) -> (Scene, Vec<Option<(String, String)>>) {
    let mut names = Vec::with_capacity(scene.forces.len());
    for k in 0..scene.forces.len() {
        let Force::Link {
            name,
            body1,
            marker1,
            axis: Some(a),
            ..
        } = &scene.forces[k]
        else {
            names.push(None);
            continue;
        };
        let marker = format!("{AXIS_MARKER}{name}");
        let body = body1.clone();
        let markers = if body == GROUND {
            &mut scene.ground
        } else {
            match scene.bodies.iter_mut().find(|b| b.name == body) {
                Some(b) => &mut b.markers,
                None => {
                    names.push(None);
                    continue;
                }
            }
        };
        let p1 = markers
            .iter()
            .find(|m| &m.name == marker1)
            .map_or(Vector3::zeros(), |m| m.position.vec());
        let position = p1 + a.vec().normalize();
        markers.push(Marker {
            name: marker.clone(),
            position: V3(position.into()),
        });
        names.push(Some((body, marker)));
    }
    (scene, names)
}
