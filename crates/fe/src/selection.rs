//! Which vectors make the dynamic part of a body's Craig–Bampton basis
//! (`BeamBodySpec::mode_selection`, docs/methods.md §1.6): the lowest fixed-interface
//! normal modes (the default), the normal modes the body's loads excite most
//! ([`crate::participation`]), load-dependent Ritz vectors ([`crate::ritz`]), or the proper
//! orthogonal modes of a pilot run ([`crate::pod`]).
//! `normal_modes` counts the kept vectors in every case; with `axial_modes` > 0 the
//! selection applies to the vectors that are not purely axial, and the axial normal modes
//! are added as before.

use flexmbd_core::InvalidValue;
use nalgebra::DMatrix;
use serde::{Deserialize, Serialize};

use crate::assembly::{DofSets, Mesh};
use crate::bounds::SPARSE_FROM_DOFS;
use crate::craig_bampton::{InteriorBasis, InteriorProblem};
use crate::error::FeError;
use crate::inertia_loads::inertia_loads;
use crate::modal::{Eigenpairs, generalized_eigen};
use crate::spec::BeamBodySpec;
use crate::{participation, pod, ritz};

/// How the dynamic vectors of a body's basis are chosen (docs/methods.md §1.6).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub enum ModeSelection {
    /// The `normal_modes` lowest fixed-interface normal modes.
    #[default]
    LowestFrequency,
    /// The `normal_modes` fixed-interface normal modes, among the lowest `mode_candidates`
    /// (default: all), with the largest share of the static response to the body's
    /// inertia and interface loads; kept in ascending frequency.
    Participation,
    /// `normal_modes` load-dependent Ritz vectors of the same loads (Wilson, Yuan &
    /// Dickens 1982), with their Ritz frequencies.
    LoadRitz,
    /// The `normal_modes` proper orthogonal modes of a pilot run of the scene with the
    /// lowest `mode_candidates` normal modes (Kerschen et al. 2005; [`crate::pod`]), with
    /// their Ritz frequencies. Needs the pilot's record ([`BeamBodySpec::pilot`]), which the
    /// `flexmbd` facade fills in when it prepares a scene.
    ProperOrthogonal,
}

impl ModeSelection {
    /// Every selection, in declaration order.
    pub const ALL: [ModeSelection; 4] = [
        ModeSelection::LowestFrequency,
        ModeSelection::Participation,
        ModeSelection::LoadRitz,
        ModeSelection::ProperOrthogonal,
    ];

    /// The name written in scenes and on the command line (`--set …mode_selection=NAME`).
    pub fn name(self) -> &'static str {
        match self {
            ModeSelection::LowestFrequency => "LowestFrequency",
            ModeSelection::Participation => "Participation",
            ModeSelection::LoadRitz => "LoadRitz",
            ModeSelection::ProperOrthogonal => "ProperOrthogonal",
        }
    }
}

/// `mode_candidates` only with `Participation` or `ProperOrthogonal`, at least
/// `normal_modes` and at most the interior DOFs left after the axial modes;
/// `pilot_duration` only with `ProperOrthogonal`, finite and positive. Each refusal names
/// the field and value.
pub(crate) fn check(spec: &BeamBodySpec) -> Result<(), InvalidValue> {
    check_sparse_route(spec)?;
    if let Some(d) = spec.pilot_duration {
        if spec.mode_selection != ModeSelection::ProperOrthogonal {
            return Err(InvalidValue::new(
                "pilot_duration",
                d,
                format!(
                    "only used with mode_selection: ProperOrthogonal (this body has {})",
                    spec.mode_selection.name()
                ),
            ));
        }
        if !(d.is_finite() && d > 0.0) {
            return Err(InvalidValue::new(
                "pilot_duration",
                d,
                "must be finite and positive (s)",
            ));
        }
    }
    let Some(c) = spec.mode_candidates else {
        return Ok(());
    };
    if !matches!(
        spec.mode_selection,
        ModeSelection::Participation | ModeSelection::ProperOrthogonal
    ) {
        return Err(InvalidValue::new(
            "mode_candidates",
            c,
            format!(
                "only used with mode_selection: Participation or ProperOrthogonal (this body has {})",
                spec.mode_selection.name()
            ),
        ));
    }
    if c < spec.normal_modes {
        return Err(InvalidValue::new(
            "mode_candidates",
            c,
            format!(
                "must be at least normal_modes ({}): the kept modes are chosen among the candidates",
                spec.normal_modes
            ),
        ));
    }
    let interior = interior_after_axial(spec);
    if c > interior {
        return Err(InvalidValue::new(
            "mode_candidates",
            c,
            format!(
                "the model has only {interior} interior DOFs (after {} axial modes) to take candidate modes from",
                spec.axial_modes
            ),
        ));
    }
    Ok(())
}

/// A beam of at least [`SPARSE_FROM_DOFS`] FE DOFs is reduced on sparse matrices with its
/// lowest fixed-interface modes only: the other selections and the axial modes start from
/// every fixed-interface mode (a dense n_i × n_i eigenproblem) or from the dense mass matrix,
/// so they are refused there, naming the field and the reason.
fn check_sparse_route(spec: &BeamBodySpec) -> Result<(), InvalidValue> {
    let n = spec.n_fe_dofs();
    if n < SPARSE_FROM_DOFS {
        return Ok(());
    }
    let why = |what: &str| {
        format!(
            "{what}; this beam has {n} FE DOFs, at least {SPARSE_FROM_DOFS}, and is reduced on \
             sparse matrices with its lowest fixed-interface modes only (use LowestFrequency, \
             or fewer elements)"
        )
    };
    if spec.mode_selection != ModeSelection::LowestFrequency {
        return Err(InvalidValue::new(
            "mode_selection",
            spec.mode_selection.name(),
            why("needs every fixed-interface mode or the dense mass matrix"),
        ));
    }
    if spec.axial_modes > 0 {
        return Err(InvalidValue::new(
            "axial_modes",
            spec.axial_modes,
            why("the axial modes are picked among every fixed-interface mode"),
        ));
    }
    Ok(())
}

/// The interior DOFs of `spec`'s fixed-interface problem left after its axial modes: the
/// most candidate modes a selection can take.
pub(crate) fn interior_after_axial(spec: &BeamBodySpec) -> usize {
    spec.n_fe_dofs()
        .saturating_sub(spec.frame_dofs().len() + spec.boundary.len())
        .saturating_sub(spec.axial_modes)
}

/// `field = value` asks for more normal modes than the `available` ones that are not purely
/// axial.
fn too_few_modes(field: &str, value: usize, available: usize) -> FeError {
    FeError::Invalid(InvalidValue::new(
        field,
        value,
        format!("the model has only {available} normal modes that are not purely axial"),
    ))
}

/// The dynamic basis of `spec` (a selection other than the default path of
/// [`crate::preprocess`]) on the fixed-interface problem `p` of `mesh` with mass `m`.
pub fn dynamic_basis(
    spec: &BeamBodySpec,
    mesh: &Mesh,
    m: &DMatrix<f64>,
    sets: &DofSets,
    p: &InteriorProblem,
) -> Result<InteriorBasis, FeError> {
    let n = spec.normal_modes;
    if spec.mode_selection == ModeSelection::LoadRitz && spec.axial_modes == 0 {
        // No eigenproblem needed.
        let loads = inertia_loads(mesh, m, sets, p.x_static);
        return ritz::load_ritz(p, &loads, n, &DMatrix::zeros(p.kii.nrows(), 0));
    }
    let all = generalized_eigen(p.kii, p.mii, &format!("{}: fixed-interface modes", p.name))?;
    let (other, axial) = if spec.axial_modes > 0 {
        split_axial(&all, mesh, sets)
    } else {
        ((0..all.omega_sq.len()).collect(), Vec::new())
    };
    if axial.len() < spec.axial_modes {
        return Err(FeError::Invalid(InvalidValue::new(
            "axial_modes",
            spec.axial_modes,
            format!(
                "the model has only {} purely axial normal modes (a straight beam along body x \
                 has one per interior axial DOF)",
                axial.len()
            ),
        )));
    }
    let loads = inertia_loads(mesh, m, sets, p.x_static);
    let chosen = match spec.mode_selection {
        ModeSelection::LowestFrequency => pick(&all, &other[..n.min(other.len())]),
        ModeSelection::Participation => {
            let n_candidates = spec.mode_candidates.unwrap_or(other.len());
            if n_candidates > other.len() {
                return Err(too_few_modes("mode_candidates", n_candidates, other.len()));
            }
            let candidates = pick(&all, &other[..n_candidates]);
            let shares = participation::static_response_shares(
                p,
                &candidates.vectors,
                &candidates.omega_sq,
                &loads,
            );
            let mut keep: Vec<usize> = participation::rank(&shares).into_iter().take(n).collect();
            keep.sort_unstable();
            let columns: Vec<usize> = keep.iter().map(|&k| other[k]).collect();
            pick(&all, &columns)
        }
        ModeSelection::ProperOrthogonal => proper_orthogonal(spec, p, &all, &other, &axial)?,
        ModeSelection::LoadRitz => {
            // Ritz vectors clear of every axial mode when axial modes are kept apart.
            let avoid = if spec.axial_modes > 0 {
                pick(&all, &axial).vectors
            } else {
                DMatrix::zeros(p.kii.nrows(), 0)
            };
            ritz::load_ritz(p, &loads, n, &avoid)?
        }
    };
    if chosen.omega_sq.len() < n {
        return Err(too_few_modes("normal_modes", n, other.len()));
    }
    Ok(merge(chosen, pick(&all, &axial[..spec.axial_modes])))
}

/// The proper orthogonal modes of `spec`'s pilot record ([`crate::pod`]) among the lowest
/// [`pod::candidate_count`] eigenpairs of `other` (not purely axial); the record's rows are
/// the pilot's dynamic modes, those candidates and the `axial_modes` lowest of `axial` in
/// ascending frequency (the `LowestFrequency` basis of [`pod::pilot_spec`]).
fn proper_orthogonal(
    spec: &BeamBodySpec,
    p: &InteriorProblem,
    all: &Eigenpairs,
    other: &[usize],
    axial: &[usize],
) -> Result<InteriorBasis, FeError> {
    let n = spec.normal_modes;
    if n == 0 {
        return Ok(pick(all, &[]));
    }
    let Some(record) = &spec.pilot else {
        return Err(FeError::Invalid(InvalidValue::new(
            "mode_selection",
            ModeSelection::ProperOrthogonal.name(),
            "needs the modal coordinates of a pilot run of the scene, which the flexmbd \
             facade records when it prepares a scene (Simulation::new, simulate, sweep): a \
             body model on its own has no pilot (methods.md §1.6)",
        )));
    };
    let k = pod::candidate_count(spec);
    if k > other.len() {
        return Err(too_few_modes("mode_candidates", k, other.len()));
    }
    let mut pilot_modes: Vec<usize> = other[..k]
        .iter()
        .chain(&axial[..spec.axial_modes.min(axial.len())])
        .copied()
        .collect();
    pilot_modes.sort_unstable();
    let rows: Vec<usize> = other[..k]
        .iter()
        .map(|c| pilot_modes.iter().position(|m| m == c).unwrap_or(0))
        .collect();
    if record.coordinates.nrows() != pilot_modes.len() {
        return Err(FeError::Dimension {
            what: format!("{}: the pilot run's modal coordinates", p.name),
            detail: format!(
                "{} recorded per sample, the pilot's basis has {} normal modes",
                record.coordinates.nrows(),
                pilot_modes.len()
            ),
        });
    }
    let eta = record.coordinates.select_rows(&rows);
    pod::proper_orthogonal_modes(p, &pick(all, &other[..k]), &eta, n)
}

/// Indices of the eigenpairs that are not purely axial, and of the purely axial ones
/// (only Ux rows non-zero, the test of `BeamBodySpec::axial_modes`).
fn split_axial(all: &Eigenpairs, mesh: &Mesh, sets: &DofSets) -> (Vec<usize>, Vec<usize>) {
    let d = mesh.dofs_per_node();
    let (mut other, mut axial) = (Vec::new(), Vec::new());
    for j in 0..all.omega_sq.len() {
        let (mut ux, mut rest) = (0.0_f64, 0.0_f64);
        for (a, &dof) in sets.i.iter().enumerate() {
            let v = all.vectors[(a, j)].abs();
            if dof % d == 0 {
                ux = ux.max(v);
            } else {
                rest = rest.max(v);
            }
        }
        if rest <= 1e-8 * ux {
            axial.push(j);
        } else {
            other.push(j);
        }
    }
    (other, axial)
}

fn pick(all: &Eigenpairs, columns: &[usize]) -> InteriorBasis {
    InteriorBasis {
        vectors: all.vectors.select_columns(columns),
        omega_sq: columns.iter().map(|&c| all.omega_sq[c]).collect(),
    }
}

/// The chosen vectors and the axial modes together, in ascending ω² (stable: the chosen
/// first on a tie).
fn merge(chosen: InteriorBasis, axial: InteriorBasis) -> InteriorBasis {
    if axial.omega_sq.is_empty() {
        return chosen;
    }
    let mut order: Vec<(f64, bool, usize)> = chosen
        .omega_sq
        .iter()
        .enumerate()
        .map(|(j, &w)| (w, false, j))
        .chain(
            axial
                .omega_sq
                .iter()
                .enumerate()
                .map(|(j, &w)| (w, true, j)),
        )
        .collect();
    order.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
    let n_i = chosen.vectors.nrows();
    let mut vectors = DMatrix::zeros(n_i, order.len());
    for (c, &(_, is_axial, j)) in order.iter().enumerate() {
        let src = if is_axial {
            &axial.vectors
        } else {
            &chosen.vectors
        };
        vectors.set_column(c, &src.column(j));
    }
    InteriorBasis {
        vectors,
        omega_sq: order.iter().map(|o| o.0).collect(),
    }
}
