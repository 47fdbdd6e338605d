//! Force elements, written once for every formulation over its [`MarkerKinematics`]
//! (docs/methods.md §2.6). Every element's generalized force is the virtual work of its
//! marker forces, Q_i += ∂r_P/∂q_i · F_P, through the formulation's marker Jacobians.
//!
//! **Spring–damper** between markers P1 and P2: with d = r_P2 − r_P1,
//! l = |d|, n = d/l and the tension f = k (l − l₀) + c n·(ṙ_P2 − ṙ_P1), the markers feel −f n
//! (at P2) and +f n (at P1), so Q += −f Jᵀn with J = ∂d/∂q. Tangents:
//! K += Jᵀ(k nnᵀ + f/l (I − nnᵀ)) J and C += c Jᵀ nnᵀ J; the terms from ∂J/∂q and the damper's
//! ∂l̇/∂q are left out (exact for rigid bodies in natural coordinates without a damper; a
//! tangent only steers Newton). Its potential energy is ½ k (l − l₀)².
//! The free length l₀ is the scene's `free_length`, or the markers' distance at the start.
//!
//! **Link** (nonlinear laws, [`crate::laws`]) and **tyre** on a road ([`crate::roads`]):
//! see [`Link`] and [`Tyre`].
//!
//! A sensor reads an element's tension and length through [`ForceElements::reading`], the
//! same code as its forces. Evaluating the elements allocates nothing: the Jacobian scratch
//! is sized once when they are compiled.

mod link;
mod load;
mod tyre;

use flexmbd_core::{ElementReading, MarkerKinematics, SystemTerms};
use nalgebra::{DVector, Matrix3, Vector3};

use crate::error::ModelError;
use crate::inputs::InputSlots;
use crate::prepared::{MarkerId, PreparedScene};
use crate::scene::Force;

pub use link::Link;
pub(crate) use link::add_axis_markers;
pub use load::Load;
pub(crate) use load::{add_load_axis_markers, runs_flexible};
pub use tyre::Tyre;

/// A linear spring–damper between two markers, `M` being the formulation's marker handle.
#[derive(Clone, Debug)]
pub struct SpringDamper<M> {
    /// Marker P1 (the force's `marker1`).
    pub first: M,
    /// Marker P2 (the force's `marker2`).
    pub second: M,
    /// Stiffness k (N/m).
    pub stiffness: f64,
    /// Damping c (N·s/m).
    pub damping: f64,
    /// Free length l₀ (m).
    pub free_length: f64,
    /// The `Scale` input that multiplies k and c, if any ([`crate::inputs`]).
    pub scale: Option<InputSlots>,
}

impl<M> SpringDamper<M> {
    /// k and c now: the scene's, times the `Scale` input's factors if it has one.
    fn coefficients(&self) -> (f64, f64) {
        match &self.scale {
            None => (self.stiffness, self.damping),
            Some(s) => (self.stiffness * s.get(0), self.damping * s.get(1)),
        }
    }
}

/// One compiled force element.
#[derive(Clone, Debug)]
pub enum Element<M> {
    /// A linear spring–damper.
    SpringDamper(SpringDamper<M>),
    /// A link of nonlinear laws.
    Link(Link<M>),
    /// A tyre on a road.
    Tyre(Tyre<M>),
    /// An external force and torque on a marker.
    Load(Load<M>),
}

/// The Jacobian scratch of the element being evaluated.
#[derive(Clone, Debug, Default)]
pub(crate) struct Scratch {
    /// (coordinate, ∂d/∂q_i) or (coordinate, ∂r_W/∂q_i).
    pub(crate) columns: Vec<(usize, Vector3<f64>)>,
    /// (coordinate, ∂l/∂q_i) of a link along an axis.
    pub(crate) gradient: Vec<(usize, f64)>,
    /// `columns` and `gradient` with one entry per coordinate, for the tangents.
    pub(crate) merged_columns: Vec<(usize, Vector3<f64>)>,
    pub(crate) merged_gradient: Vec<(usize, f64)>,
    /// Per coordinate: its place in the merged list being built, or `usize::MAX`.
    pub(crate) slot: Vec<usize>,
}

/// The force elements of a scene, compiled for one formulation, with the scratch their
/// Jacobians need (sized once: evaluating them allocates nothing).
#[derive(Clone, Debug)]
pub struct ForceElements<M> {
    elements: Vec<Element<M>>,
    scratch: Scratch,
}

impl<M> Default for ForceElements<M> {
    fn default() -> Self {
        ForceElements {
            elements: Vec::new(),
            scratch: Scratch::default(),
        }
    }
}

impl<M> ForceElements<M> {
    /// Every marker handle the elements hold (both ends, a link's axis marker, a load's
    /// axis markers), for a formulation to annotate its handles after compiling them (the
    /// relative formulation's marker table).
    pub fn markers_mut(&mut self) -> impl Iterator<Item = &mut M> {
        self.elements.iter_mut().flat_map(|element| {
            let markers: Vec<&mut M> = match element {
                Element::SpringDamper(s) => vec![&mut s.first, &mut s.second],
                Element::Link(l) => {
                    let mut m = vec![&mut l.first, &mut l.second];
                    m.extend(l.axis.as_mut());
                    m
                }
                Element::Tyre(t) => vec![&mut t.wheel],
                Element::Load(l) => {
                    let mut m = vec![&mut l.at];
                    m.extend(l.axes.iter_mut());
                    m
                }
            };
            markers
        })
    }

    /// The marker handles of each element (both ends, a link's axis marker, a load's axis
    /// markers), element by element: a formulation declares from them which coordinates
    /// an element's tangents couple (`flexmbd_core::DeclaredPattern`).
    pub fn markers_of_each(&self) -> Vec<Vec<&M>> {
        self.elements
            .iter()
            .map(|element| match element {
                Element::SpringDamper(s) => vec![&s.first, &s.second],
                Element::Link(l) => {
                    let mut m = vec![&l.first, &l.second];
                    m.extend(l.axis.as_ref());
                    m
                }
                Element::Tyre(t) => vec![&t.wheel],
                Element::Load(l) => {
                    let mut m = vec![&l.at];
                    m.extend(l.axes.iter());
                    m
                }
            })
            .collect()
    }

    /// Compile the scene's force elements for a formulation: `marker` maps a marker to the
    /// formulation's handle, `kinematics` at (`q0`, `qd0`) gives the markers' start positions
    /// (for free lengths left to the start); `n_coordinates` bounds the Jacobian columns.
    pub fn new<K>(
        prepared: &PreparedScene,
        mut marker: impl FnMut(MarkerId) -> M,
        kinematics: &K,
        q0: &DVector<f64>,
        qd0: &DVector<f64>,
        n_coordinates: usize,
    ) -> Result<Self, ModelError>
    where
        K: MarkerKinematics<Marker = M>,
    {
        let scene = prepared.scene();
        let mut elements = Vec::with_capacity(scene.forces.len());
        let ends = prepared.force_markers().iter();
        for (k, ((force, pair), axis)) in scene
            .forces
            .iter()
            .zip(ends)
            .zip(prepared.force_axis_markers())
            .enumerate()
        {
            let input = prepared.inputs().force_slots(k);
            let (first, second) = (marker(pair.first), marker(pair.second));
            elements.push(match force {
                Force::SpringDamper {
                    stiffness, damping, ..
                } => {
                    let (r1, _) = kinematics.marker_state(&first, q0, qd0);
                    let (r2, _) = kinematics.marker_state(&second, q0, qd0);
                    Element::SpringDamper(SpringDamper {
                        first,
                        second,
                        stiffness: *stiffness,
                        damping: *damping,
                        free_length: force.spring_free_length(&scene.origin, &r1, &r2)?,
                        scale: input,
                    })
                }
                Force::Link { .. } => Element::Link(Link {
                    scale: input,
                    ..Link::new(
                        force,
                        &scene.origin,
                        (first, second, axis.map(&mut marker)),
                        kinematics,
                        q0,
                        qd0,
                    )?
                }),
                Force::Tyre { .. } => {
                    Element::Tyre(Tyre::new(force, &scene.roads, first, prepared.inputs()))
                }
                Force::Load { .. } => {
                    let axes = prepared.load_axis_markers()[k].iter();
                    Element::Load(Load {
                        input,
                        ..Load::new(force, first, axes.map(|&m| marker(m)).collect())
                    })
                }
            });
        }
        Ok(ForceElements {
            elements,
            scratch: Scratch {
                columns: Vec::with_capacity(3 * n_coordinates),
                gradient: Vec::with_capacity(3 * n_coordinates),
                merged_columns: Vec::with_capacity(n_coordinates),
                merged_gradient: Vec::with_capacity(n_coordinates),
                slot: vec![usize::MAX; n_coordinates],
            },
        })
    }

    /// True when the scene has no force elements.
    pub fn is_empty(&self) -> bool {
        self.elements.is_empty()
    }

    /// The compiled elements, in the order of the scene's `forces`.
    pub fn elements(&self) -> &[Element<M>] {
        &self.elements
    }

    /// Add the elements' generalized forces Q at (q, q̇) to `out.forces`, and with `tangents`
    /// their K and C to `out.stiffness` and `out.damping`.
    pub fn add_forces<K>(
        &mut self,
        kinematics: &mut K,
        q: &DVector<f64>,
        qd: &DVector<f64>,
        tangents: bool,
        out: &mut SystemTerms,
    ) where
        K: MarkerKinematics<Marker = M>,
    {
        let scratch = &mut self.scratch;
        for element in &self.elements {
            match element {
                Element::SpringDamper(spring) => {
                    add_spring(spring, kinematics, q, qd, tangents, scratch, out)
                }
                Element::Link(link) => link.add_forces(kinematics, q, qd, tangents, scratch, out),
                Element::Tyre(tyre) => {
                    tyre.add_forces(kinematics, q, qd, tangents, &mut scratch.columns, out)
                }
                Element::Load(load) => load.add_forces(kinematics, q, qd, out),
            }
        }
    }

    /// The tension (a tyre: normal force) and length (a tyre: deflection) of element `k` at
    /// (q, q̇).
    pub fn reading<K>(
        &self,
        k: usize,
        kinematics: &K,
        q: &DVector<f64>,
        qd: &DVector<f64>,
    ) -> ElementReading
    where
        K: MarkerKinematics<Marker = M>,
    {
        match &self.elements[k] {
            Element::SpringDamper(spring) => {
                let (_, _, l, f) = spring_state(spring, kinematics, q, qd);
                ElementReading {
                    force: f,
                    length: l,
                }
            }
            Element::Link(link) => link.reading(kinematics, q, qd),
            Element::Tyre(tyre) => tyre.reading(kinematics, q, qd),
            Element::Load(load) => load.reading(),
        }
    }

    /// Potential energy of the elements at q (J): ½ k (l − l₀)² of a spring–damper, the
    /// integral of a link's spring law from its start length, ½ K δ² of a tyre in contact.
    pub fn potential_energy<K>(&self, kinematics: &K, q: &DVector<f64>, qd: &DVector<f64>) -> f64
    where
        K: MarkerKinematics<Marker = M>,
    {
        self.elements
            .iter()
            .map(|element| match element {
                Element::SpringDamper(spring) => {
                    let (r1, _) = kinematics.marker_state(&spring.first, q, qd);
                    let (r2, _) = kinematics.marker_state(&spring.second, q, qd);
                    let stretch = (r2 - r1).norm() - spring.free_length;
                    0.5 * spring.coefficients().0 * stretch * stretch
                }
                Element::Link(link) => link.potential_energy(kinematics, q, qd),
                Element::Tyre(tyre) => tyre.potential_energy(kinematics, q, qd),
                Element::Load(_) => 0.0,
            })
            .sum()
    }
}

/// A spring–damper's direction n, distance l... at (q, q̇): (d, n, l, f).
fn spring_state<M, K>(
    spring: &SpringDamper<M>,
    kinematics: &K,
    q: &DVector<f64>,
    qd: &DVector<f64>,
) -> (Vector3<f64>, Vector3<f64>, f64, f64)
where
    K: MarkerKinematics<Marker = M>,
{
    let (r1, v1) = kinematics.marker_state(&spring.first, q, qd);
    let (r2, v2) = kinematics.marker_state(&spring.second, q, qd);
    let d = r2 - r1;
    let l = d.norm();
    let n = d / l;
    let (stiffness, damping) = spring.coefficients();
    let f = stiffness * (l - spring.free_length) + damping * n.dot(&(v2 - v1));
    (d, n, l, f)
}

/// A spring–damper's Q (and K, C).
fn add_spring<M, K>(
    spring: &SpringDamper<M>,
    kinematics: &mut K,
    q: &DVector<f64>,
    qd: &DVector<f64>,
    tangents: bool,
    scratch: &mut Scratch,
    out: &mut SystemTerms,
) where
    K: MarkerKinematics<Marker = M>,
{
    let (_, n, l, f) = spring_state(spring, kinematics, q, qd);
    line_columns(
        kinematics,
        &spring.first,
        &spring.second,
        q,
        &mut scratch.columns,
    );
    for &(i, c) in scratch.columns.iter() {
        out.forces[i] -= f * n.dot(&c);
    }
    if tangents {
        merge_coordinates(
            &scratch.columns,
            &mut scratch.slot,
            &mut scratch.merged_columns,
        );
        add_tangents(spring, &n, f, l, &scratch.merged_columns, out);
    }
}

/// `merged` = `entries` with the entries of one coordinate summed into one, in the order
/// the coordinates first appear (`slot`: all `usize::MAX`, and left so). The tangent loops
/// run over every pair of entries: an element whose markers move with the same joints (a
/// strut between the chassis and a wheel carrier both move with the chassis's six) lists
/// those coordinates twice or three times, which would make 2–9 times the pairs. Entries
/// with no repeated coordinate come out as they went in.
pub(crate) fn merge_coordinates<T: Copy + std::ops::AddAssign>(
    entries: &[(usize, T)],
    slot: &mut [usize],
    merged: &mut Vec<(usize, T)>,
) {
    merged.clear();
    for &(i, v) in entries {
        if slot[i] == usize::MAX {
            slot[i] = merged.len();
            merged.push((i, v));
        } else {
            merged[slot[i]].1 += v;
        }
    }
    for &(i, _) in merged.iter() {
        slot[i] = usize::MAX;
    }
}

/// The columns ∂d/∂q_i of d = r_P2 − r_P1.
pub(crate) fn line_columns<M, K>(
    kinematics: &mut K,
    first: &M,
    second: &M,
    q: &DVector<f64>,
    columns: &mut Vec<(usize, Vector3<f64>)>,
) where
    K: MarkerKinematics<Marker = M>,
{
    columns.clear();
    kinematics.marker_jacobian(second, q, &mut |i, c| columns.push((i, c)));
    kinematics.marker_jacobian(first, q, &mut |i, c| columns.push((i, -c)));
}

/// K += Jᵀ(k nnᵀ + f/l (I − nnᵀ)) J, C += c Jᵀ nnᵀ J over the element's Jacobian columns.
fn add_tangents<M>(
    spring: &SpringDamper<M>,
    n: &Vector3<f64>,
    f: f64,
    l: f64,
    columns: &[(usize, Vector3<f64>)],
    out: &mut SystemTerms,
) {
    let (stiffness, damping) = spring.coefficients();
    add_line_tangents(n, stiffness, f, l, damping, columns, out);
}

/// K += Jᵀ(k nnᵀ + f/l (I − nnᵀ)) J, C += c Jᵀ nnᵀ J with the slopes k = ∂f/∂l and
/// c = ∂f/∂l̇ of a force along the line of two markers.
pub(crate) fn add_line_tangents(
    n: &Vector3<f64>,
    k: f64,
    f: f64,
    l: f64,
    c: f64,
    columns: &[(usize, Vector3<f64>)],
    out: &mut SystemTerms,
) {
    let nn = n * n.transpose();
    let stiffness = nn * k + (Matrix3::identity() - nn) * (f / l);
    for &(i, ci) in columns {
        let kc = stiffness * ci;
        let cc = c * n.dot(&ci);
        for &(j, cj) in columns {
            out.stiffness[(j, i)] += cj.dot(&kc);
            out.damping[(j, i)] += cc * n.dot(&cj);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn merge_coordinates_sums_repeated_coordinates_in_first_appearance_order() {
        let mut slot = vec![usize::MAX; 6];
        let mut merged = Vec::with_capacity(6);
        // A strut's columns: its wheel-side marker's (4, 1, 5), then its chassis marker's
        // (4, 1) again.
        let entries = [(4, 1.0), (1, 2.0), (5, -3.0), (4, 0.5), (1, -0.25)];
        merge_coordinates(&entries, &mut slot, &mut merged);
        assert_eq!(merged, [(4, 1.5), (1, 1.75), (5, -3.0)]);
        assert!(slot.iter().all(|&s| s == usize::MAX), "{slot:?}");
        // No repeated coordinate: the entries as they went in.
        let distinct = [(2, Vector3::<f64>::new(1.0, -0.0, 3.0)), (0, Vector3::x())];
        let mut merged = Vec::new();
        merge_coordinates(&distinct, &mut slot, &mut merged);
        assert_eq!(merged, distinct);
        assert_eq!(merged[0].1.y.to_bits(), (-0.0f64).to_bits());
    }
}
