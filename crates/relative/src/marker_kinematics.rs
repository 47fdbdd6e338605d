//! The relative formulation's marker kinematics ([`MarkerKinematics`]), over which the force
//! elements of `flexmbd_model::force_elements` are evaluated.
//!
//! A marker's position and velocity are those of the last kinematic pass (the tree's frames,
//! §4.5 steps 1–3). Its Jacobian ∂r_P/∂z is built like the cut-joint rows
//! (docs/methods.md §4.4–§4.6): the marker's velocity per unit rate of every elementary joint
//! on its body's path, u_a = ṡ_a + ω_a × r_P (the twist in the s form), plus the node's modal
//! columns A X^t of a flexible body, in w, then folded into z through L.

use flexmbd_core::MarkerKinematics;
use nalgebra::{DMatrix, DVector, Vector3};

use crate::Relative;
use crate::kinematics::point_at;
use crate::topology::Side;

/// Scratch of one marker Jacobian, sized once: the marker's (w, ∂r_P/∂w_w) columns (a
/// marker moves with the joints on its body's path only: a handful of the n_w columns), and
/// for a marker that moves with node joints ∂r_P/∂w (3 × n_w) and ∂r_P/∂z (3 × n_z), both all
/// zeros between queries, with the columns the current query touches.
#[derive(Clone, Debug, Default)]
pub(crate) struct MarkerJacobian {
    columns: Vec<(usize, Vector3<f64>)>,
    jw: DMatrix<f64>,
    jz: DMatrix<f64>,
    touched_w: Vec<usize>,
    touched_z: Vec<usize>,
    z_is_touched: Vec<bool>,
}

impl MarkerJacobian {
    pub(crate) fn new(n_w: usize, n_z: usize) -> Self {
        MarkerJacobian {
            columns: Vec::with_capacity(n_w),
            jw: DMatrix::zeros(3, n_w),
            jz: DMatrix::zeros(3, n_z),
            touched_w: Vec::with_capacity(n_w),
            touched_z: Vec::with_capacity(n_z),
            z_is_touched: vec![false; n_z],
        }
    }
}

/// What one column of a marker's Jacobian comes from.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum ColumnSource {
    /// Elementary joint `a` on the marker's body's path.
    Joint(usize),
    /// Mode `m` of the marker's node.
    Mode(usize),
}

impl MarkerKinematics for Relative {
    type Marker = Side;

    /// From the last kinematic pass, which the caller has run at (q, q̇): the marker
    /// table's row when it is current (`marker_table.rs`).
    fn marker_state(
        &self,
        marker: &Side,
        _q: &DVector<f64>,
        _qd: &DVector<f64>,
    ) -> (Vector3<f64>, Vector3<f64>) {
        self.forces
            .marker_table
            .state(marker)
            .unwrap_or_else(|| point_at(self, marker))
    }

    fn marker_jacobian(
        &mut self,
        marker: &Side,
        _q: &DVector<f64>,
        visit: &mut dyn FnMut(usize, Vector3<f64>),
    ) {
        if let Some(columns) = self.forces.marker_table.columns(marker) {
            for &(i, c) in columns {
                visit(i, c);
            }
            return;
        }
        let (p, _) = point_at(self, marker);
        self.jacobian_at(marker, &p, visit);
    }
}

impl Relative {
    /// The non-zero columns (z, ∂r_P/∂z) of marker `s` at its position `p`, in increasing z.
    pub(crate) fn jacobian_at(
        &mut self,
        marker: &Side,
        p: &Vector3<f64>,
        visit: &mut dyn FnMut(usize, Vector3<f64>),
    ) {
        let mut scratch = std::mem::take(&mut self.forces.marker_jacobian);
        let columns = &mut scratch.columns;
        columns.clear();
        self.point_columns(marker, p, columns);
        columns.sort_unstable_by_key(|&(w, _)| w);
        let distinct = columns.windows(2).all(|pair| pair[0].0 < pair[1].0);
        if distinct && columns.last().is_none_or(|&(w, _)| w < self.tree.n_z) {
            // Every column is a z coordinate's (L's row is (w, 1)), each once: J_z's column
            // is 0 + 1·J_w's (the 0 + turns a −0 into the +0 the sum gives), in increasing z.
            for &(w, u) in columns.iter() {
                let column = u.map(|x| 0.0 + x);
                if column != Vector3::zeros() {
                    visit(w, column);
                }
            }
        } else {
            self.fold_through_l(&mut scratch, visit);
        }
        self.forces.marker_jacobian = scratch;
    }

    /// The marker `s`'s columns (w, ∂r_P/∂w_w) at the point `p`: u_a = ṡ_a + ω_a × r_P of the
    /// elementary joints on its body's path, then A X^t of its node's modes.
    fn point_columns(&self, s: &Side, p: &Vector3<f64>, columns: &mut Vec<(usize, Vector3<f64>)>) {
        let Some(k) = s.body else { return };
        let b = &self.bodies[k];
        for &a in &self.tree.paths[b.frame] {
            columns.push(self.column(s, p, ColumnSource::Joint(a)));
        }
        if s.node.is_some() {
            for m in 0..b.n_modes {
                columns.push(self.column(s, p, ColumnSource::Mode(m)));
            }
        }
    }

    /// Where the columns of marker `s` come from, in the order of `point_columns`: the
    /// elementary joints on its body's path, then its node's modes (allocates: for
    /// compiling the marker table).
    pub(crate) fn column_sources(&self, s: &Side) -> Vec<ColumnSource> {
        let Some(k) = s.body else { return Vec::new() };
        let b = &self.bodies[k];
        let mut sources: Vec<ColumnSource> = self.tree.paths[b.frame]
            .iter()
            .map(|&a| ColumnSource::Joint(a))
            .collect();
        if s.node.is_some() {
            sources.extend((0..b.n_modes).map(ColumnSource::Mode));
        }
        sources
    }

    /// The w coordinate of a column source of marker `s`.
    pub(crate) fn source_w(&self, s: &Side, source: ColumnSource) -> usize {
        match (source, s.body) {
            (ColumnSource::Joint(a), _) => self.tree.elem_w[a],
            (ColumnSource::Mode(m), Some(k)) => self.bodies[k].first_mode + m,
            (ColumnSource::Mode(_), None) => unreachable!("a ground marker has no modes"),
        }
    }

    /// One column (w, ∂r_P/∂w_w) of marker `s` at the point `p`: u_a = ṡ_a + ω_a × r_P of an
    /// elementary joint on its body's path, or A X^t_m of its node's mode m.
    #[inline(always)]
    pub(crate) fn column(
        &self,
        s: &Side,
        p: &Vector3<f64>,
        source: ColumnSource,
    ) -> (usize, Vector3<f64>) {
        match source {
            ColumnSource::Joint(a) => {
                let elem_twist = &self.frames.elem_twist[a];
                let u = elem_twist.fixed_rows::<3>(0) + elem_twist.fixed_rows::<3>(3).cross(p);
                (self.tree.elem_w[a], u)
            }
            ColumnSource::Mode(m) => {
                let b = &self.bodies[s.body.expect("a node marker is on a body")];
                let node = s.node.expect("a mode column is a node marker's");
                let col = self.frames.rotation[b.frame]
                    * Vector3::new(
                        b.node_rows.translation_entry(node, 0, m),
                        b.node_rows.translation_entry(node, 1, m),
                        b.node_rows.translation_entry(node, 2, m),
                    );
                (b.first_mode + m, col)
            }
        }
    }

    /// J_z = J_w L for a marker that moves with node joints (w entries beyond z), visited in
    /// increasing z: the sums over the touched w columns in increasing order, the same, in
    /// the same order, as over every column (the others are zero and were skipped).
    fn fold_through_l(
        &self,
        scratch: &mut MarkerJacobian,
        visit: &mut dyn FnMut(usize, Vector3<f64>),
    ) {
        let MarkerJacobian {
            columns,
            jw,
            jz,
            touched_w,
            touched_z,
            z_is_touched,
        } = scratch;
        for &(w, u) in columns.iter() {
            for r in 0..3 {
                jw[(r, w)] += u[r];
            }
            touched_w.push(w);
        }
        touched_w.dedup();
        for &w in touched_w.iter() {
            if (0..3).all(|r| jw[(r, w)] == 0.0) {
                continue;
            }
            for &(c, a) in &self.tree.l_rows[w] {
                for r in 0..3 {
                    jz[(r, c)] += a * jw[(r, w)];
                }
                if !z_is_touched[c] {
                    z_is_touched[c] = true;
                    touched_z.push(c);
                }
            }
        }
        for &w in touched_w.iter() {
            jw.column_mut(w).fill(0.0);
        }
        touched_w.clear();
        touched_z.sort_unstable();
        for &i in touched_z.iter() {
            let column = Vector3::new(jz[(0, i)], jz[(1, i)], jz[(2, i)]);
            if column != Vector3::zeros() {
                visit(i, column);
            }
            jz.column_mut(i).fill(0.0);
            z_is_touched[i] = false;
        }
        touched_z.clear();
    }
}
