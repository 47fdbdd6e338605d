//! The marker table (issue 26): the position r_P, velocity ṙ_P and Jacobian columns
//! ∂r_P/∂z of every marker a force element reads, evaluated once per dynamics pass, after the
//! kinematic pass (§4.5 steps 1–3) and before the force elements
//! (`flexmbd_model::force_elements`), which read them from here.
//!
//! Without the table an element asked for each of its markers twice (its position for the
//! element's geometry, then its Jacobian, which needs the position again), and a marker
//! shared by two elements was evaluated for each. The values are those of the same code
//! (`point_at`, the columns of `marker_kinematics.rs`), computed once: the same numbers.
//!
//! The order of a marker's columns is fixed when the scene is compiled: a marker whose
//! columns are each one z coordinate's, once (every marker of a rigid body: its path's
//! joint coordinates and its node's modes), has them listed in increasing z then
//! ([`MarkerTable::plan`]), and a pass computes them in that order; the others (a body hung
//! from a flexible node, whose path has node joints) are folded through L each pass.
//!
//! A row is current while the frames are those of the pass that filled it: the kinematic
//! pass marks the table stale ([`MarkerTable::invalidate`]), and a query on a stale table
//! (a sensor, the energy, the start lengths) is answered from the frames directly.

use nalgebra::Vector3;

use crate::Relative;
use crate::kinematics::point_at;
use crate::marker_kinematics::ColumnSource;
use crate::topology::Side;

/// The force elements' markers and their values at the last dynamics pass.
#[derive(Clone, Debug, Default)]
pub(crate) struct MarkerTable {
    /// The distinct markers (their `slot` unset).
    sides: Vec<Side>,
    position: Vec<Vector3<f64>>,
    velocity: Vec<Vector3<f64>>,
    /// The non-zero columns (z, ∂r_P/∂z) of every marker in turn, in increasing z.
    columns: Vec<(usize, Vector3<f64>)>,
    /// Row k's columns are `columns[offsets[k]..offsets[k + 1]]`.
    offsets: Vec<usize>,
    /// Per row: its column sources in increasing z when each is one z coordinate's, once
    /// (`None`: folded through L each pass).
    direct: Vec<Option<Vec<ColumnSource>>>,
    /// The rows hold the frames' current values.
    current: bool,
}

impl MarkerTable {
    /// The row of `side`, added if the table does not hold it yet.
    pub(crate) fn row_of(&mut self, side: &Side) -> usize {
        let key = Side {
            slot: None,
            ..*side
        };
        if let Some(k) = self.sides.iter().position(|s| *s == key) {
            return k;
        }
        self.sides.push(key);
        self.position.push(Vector3::zeros());
        self.velocity.push(Vector3::zeros());
        self.offsets.push(0);
        self.sides.len() - 1
    }

    /// Fix each row's column order (module documentation) and make room for every row's
    /// columns (at most `n_z` each), so that filling allocates nothing.
    pub(crate) fn plan(&mut self, rel: &Relative) {
        self.offsets.push(0);
        self.columns.reserve(self.sides.len() * rel.tree.n_z);
        self.direct = self
            .sides
            .iter()
            .map(|side| {
                let mut sources = rel.column_sources(side);
                sources.sort_by_key(|&s| rel.source_w(side, s));
                let w: Vec<usize> = sources.iter().map(|&s| rel.source_w(side, s)).collect();
                let distinct = w.windows(2).all(|pair| pair[0] < pair[1]);
                (distinct && w.last().is_none_or(|&w| w < rel.tree.n_z)).then_some(sources)
            })
            .collect();
    }

    /// The frames moved: the rows are no longer theirs.
    pub(crate) fn invalidate(&mut self) {
        self.current = false;
    }

    /// Position and velocity of `side`'s row, if it has one and it is current.
    pub(crate) fn state(&self, side: &Side) -> Option<(Vector3<f64>, Vector3<f64>)> {
        let k = side.slot.filter(|_| self.current)?;
        Some((self.position[k], self.velocity[k]))
    }

    /// The Jacobian columns of `side`'s row, if it has one and it is current.
    pub(crate) fn columns(&self, side: &Side) -> Option<&[(usize, Vector3<f64>)]> {
        let k = side.slot.filter(|_| self.current)?;
        Some(&self.columns[self.offsets[k]..self.offsets[k + 1]])
    }
}

impl Relative {
    /// Evaluate every row of the marker table at the frames of the last kinematic pass.
    pub(crate) fn fill_marker_table(&mut self) {
        let mut table = std::mem::take(&mut self.forces.marker_table);
        table.columns.clear();
        for k in 0..table.sides.len() {
            let side = table.sides[k];
            let (p, v) = point_at(self, &side);
            table.position[k] = p;
            table.velocity[k] = v;
            table.offsets[k] = table.columns.len();
            let columns = &mut table.columns;
            match &table.direct[k] {
                // As `jacobian_at` on such a marker: J_z's column is 0 + 1·J_w's.
                Some(sources) => {
                    for &source in sources {
                        let (w, u) = self.column(&side, &p, source);
                        let column = u.map(|x| 0.0 + x);
                        if column != Vector3::zeros() {
                            columns.push((w, column));
                        }
                    }
                }
                None => self.jacobian_at(&side, &p, &mut |i, c| columns.push((i, c))),
            }
        }
        let rows = table.sides.len();
        table.offsets[rows] = table.columns.len();
        table.current = true;
        self.forces.marker_table = table;
    }
}
