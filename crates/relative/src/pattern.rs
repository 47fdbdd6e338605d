//! The structure of M, K, C and Φ_z, declared when the scene is compiled (issue 26 item 2;
//! [`flexmbd_core::DeclaredPattern`]).
//!
//! In relative coordinates M = Σ_k R_kᵀ M̄_k R_k (docs/methods.md §4.5): body k's velocity
//! Z_k = R_k ż depends on the coordinates of the elementary joints on its path to the root
//! (a node joint's rate is X_P ẏ of the parent body's modes) and on its own modes, so body
//! k's term couples exactly that set, its **coordinate set**. The chassis's six coordinates
//! are in every set of a vehicle, each corner's only in its own bodies' sets: the arrow form
//! of the tree. A body's modal tangents K_ff, C_ff couple its modes (a subset of its set); a
//! force element's tangents couple the coordinates its markers move with (their bodies'
//! paths, and their bodies' modes for markers at FE nodes); a constraint row of two markers
//! involves those of its two markers, a driven tree joint's row its one coordinate (§4.6).

use flexmbd_core::DeclaredPattern;

use crate::constraints::Constraint;
use crate::system::Relative;
use crate::topology::Side;

impl Relative {
    /// The z coordinates of the elementary joints on body k's path, and its own modes when
    /// `modes`.
    fn coordinate_set(&self, k: usize, modes: bool) -> Vec<usize> {
        let b = &self.bodies[k];
        let own = if modes { b.n_modes } else { 0 };
        let mut set: Vec<usize> = self.tree.paths[b.frame]
            .iter()
            .flat_map(|&a| self.tree.elem_rate[a].iter().map(|&(c, _)| c))
            .chain(b.first_mode..b.first_mode + own)
            .collect();
        set.sort_unstable();
        set.dedup();
        set
    }

    /// The union of the sides' coordinate sets: a marker moves with its body's path, and
    /// with its body's modes only at an FE node (a ground side adds none).
    fn sides_coordinate_set<'a>(&self, sides: impl IntoIterator<Item = &'a Side>) -> Vec<usize> {
        let mut set: Vec<usize> = sides
            .into_iter()
            .filter_map(|s| Some(self.coordinate_set(s.body?, s.node.is_some())))
            .flatten()
            .collect();
        set.sort_unstable();
        set.dedup();
        set
    }

    /// The declared pattern (module documentation).
    pub(crate) fn pattern(&self) -> DeclaredPattern {
        let mut coupled: Vec<Vec<usize>> = (0..self.bodies.len())
            .map(|k| self.coordinate_set(k, true))
            .collect();
        coupled.extend(
            self.forces
                .elements
                .markers_of_each()
                .into_iter()
                .map(|markers| self.sides_coordinate_set(markers)),
        );
        coupled.retain(|group| !group.is_empty());
        let mut jacobian_rows = Vec::new();
        for c in &self.rows.constraints {
            let columns = match c {
                Constraint::Coord { z, .. } => vec![*z],
                Constraint::Point { i, j }
                | Constraint::Angle2 { i, j, .. }
                | Constraint::Slide { i, j, .. }
                | Constraint::Perp { i, j, .. }
                | Constraint::Distance { i, j, .. } => self.sides_coordinate_set([i, j]),
            };
            for _ in 0..c.rows(self.tree.dim) {
                jacobian_rows.push(columns.clone());
            }
        }
        DeclaredPattern {
            coupled,
            jacobian_rows,
        }
    }
}
