//! The interface force at a marker of a body carried by joints at several markers (a
//! connecting rod): every joint's reaction from every moving body's balance together.
//!
//! Each moving body k gives its balance W_k = [M̄_0 Ż − Q̄_v0]_rigid − gravity − the force
//! elements on it (`interface_force`), the wrench about r0_k its joints must apply. A joint's
//! reaction on body2 is Σ_c x_c {f_c; m_c} at body2's marker P2 over its constrained
//! directions (`reaction_directions`, at the bodies' present turns); body1 feels the opposite
//! at the same point. The balance rows A x = W of every body are solved for x by least
//! squares, (AᵀA + ε I) x = Aᵀ W with ε = 1e-12 of AᵀA's largest diagonal entry (a
//! Cholesky factorisation in storage sized when the sensor is compiled): the exact solution
//! when the joints are not redundant (a mechanism's balance rows are consistent: the step
//! solved its equations of motion), within ε of the minimum-norm one otherwise, as
//! `flexmbd equilibrium`'s reactions. The sensor then sums the reactions of the joints at P.
//! Scene constraints (`Distance`, `PointInPlane`) are not in these rows: a scene with them
//! is refused when the body's balance alone does not give the force.

use flexmbd_core::{Dim, SensorQuery};
use nalgebra::{DMatrix, DVector, Matrix3, Vector3};

use crate::error::ModelError;
use crate::interface_force::{BodyBalance, MarkerForces, Wrench};
use crate::prepared::{BodyId, MarkerId, PreparedScene};
use crate::reaction_directions::joint_directions;
use crate::scene::{JointKind, Scene};

/// True when every joint (but `Free`) and constraint on `marker`'s body acts at `marker`:
/// the body's balance alone gives the force there.
pub(crate) fn alone(prepared: &PreparedScene, marker: MarkerId) -> bool {
    let scene = prepared.scene();
    let joints = scene
        .joints
        .iter()
        .zip(prepared.joint_markers())
        .filter(|(j, _)| !matches!(j.kind, JointKind::Free))
        .map(|(_, pair)| [pair.first, pair.second]);
    let constraints = prepared
        .constraint_markers()
        .iter()
        .map(|pair| [pair.first, pair.second]);
    joints
        .chain(constraints)
        .flatten()
        .all(|id| id.body != marker.body || id == marker)
}

/// One joint's columns of the balance rows.
#[derive(Clone, Debug)]
struct JointColumns<M> {
    kind: JointKind,
    bodies: [Option<usize>; 2],
    /// body2's marker P2, where the reaction acts.
    second: M,
    driven: bool,
    first_column: usize,
    /// +1 when the sensor's body is this joint's body2 at P, −1 when body1 at P, 0 otherwise.
    sign: f64,
}

/// Every moving body's balance and the storage of the least-squares solve.
#[derive(Clone, Debug)]
pub(crate) struct SystemBalance<M> {
    dim: Dim,
    balances: Vec<BodyBalance>,
    /// The force elements' slots on each body.
    body_slots: Vec<Vec<usize>>,
    joints: Vec<JointColumns<M>>,
    wrenches: Vec<Wrench>,
    a: DMatrix<f64>,
    rhs: DVector<f64>,
    normal: DMatrix<f64>,
    x: DVector<f64>,
}

fn refuse(scene: &Scene, marker: MarkerId, why: &str) -> ModelError {
    let body = &scene.bodies[marker.body.map_or(0, |b| b.0)];
    ModelError::Unsupported(format!(
        "{}: the interface force at `{}`.`{}` needs the reactions of every joint (the body has \
         joints at other markers), {why}",
        scene.origin, body.name, body.markers[marker.index].name
    ))
}

impl<M> SystemBalance<M> {
    pub(crate) fn new(
        prepared: &PreparedScene,
        marker: MarkerId,
        slots: &[MarkerId],
        handle: &mut impl FnMut(MarkerId) -> M,
        mode: &mut impl FnMut(BodyId, usize) -> Option<usize>,
    ) -> Result<Self, ModelError> {
        let scene = prepared.scene();
        if let Some(c) = scene.constraints.first() {
            return Err(refuse(
                scene,
                marker,
                &format!(
                    "and the scene constraint `{}` is not among them yet",
                    c.name()
                ),
            ));
        }
        let n_bodies = scene.bodies.len();
        let driven: Vec<usize> = prepared.driver_joints().iter().map(|j| j.0).collect();
        let identity = Matrix3::identity();
        let mut joints = Vec::with_capacity(scene.joints.len());
        let mut columns = 0;
        for (j, (joint, pair)) in scene
            .joints
            .iter()
            .zip(prepared.joint_markers())
            .enumerate()
        {
            let (forces, moments) = joint_directions(
                scene.dim,
                &joint.kind,
                &identity,
                &identity,
                driven.contains(&j),
            );
            let sign = if pair.second == marker {
                1.0
            } else if pair.first == marker {
                -1.0
            } else {
                0.0
            };
            joints.push(JointColumns {
                kind: joint.kind.clone(),
                bodies: [pair.first.body.map(|b| b.0), pair.second.body.map(|b| b.0)],
                second: handle(pair.second),
                driven: driven.contains(&j),
                first_column: columns,
                sign,
            });
            columns += forces.len + moments.len;
        }
        let rows = scene.dim.n_rigid() * n_bodies;
        let body_slots = (0..n_bodies)
            .map(|k| {
                slots
                    .iter()
                    .enumerate()
                    .filter(|(_, id)| id.body == Some(BodyId(k)))
                    .map(|(s, _)| s)
                    .collect()
            })
            .collect();
        let zero = Wrench {
            origin: Vector3::zeros(),
            rotation: identity,
            force: Vector3::zeros(),
            moment: Vector3::zeros(),
        };
        Ok(SystemBalance {
            dim: scene.dim,
            balances: (0..n_bodies)
                .map(|k| BodyBalance::new(prepared, BodyId(k), mode))
                .collect(),
            body_slots,
            joints,
            wrenches: vec![zero; n_bodies],
            a: DMatrix::zeros(rows, columns),
            rhs: DVector::zeros(rows),
            normal: DMatrix::zeros(columns, columns),
            x: DVector::zeros(columns),
        })
    }

    /// Add force `f` at `point` and moment `m` on body `k` (ground: nothing) to column `c`.
    fn add(
        &mut self,
        c: usize,
        k: Option<usize>,
        point: &Vector3<f64>,
        f: &Vector3<f64>,
        m: &Vector3<f64>,
    ) {
        let Some(k) = k else { return };
        let moment = (point - self.wrenches[k].origin).cross(f) + m;
        let row = k * self.dim.n_rigid();
        match self.dim {
            Dim::Planar => {
                self.a[(row, c)] += f.x;
                self.a[(row + 1, c)] += f.y;
                self.a[(row + 2, c)] += moment.z;
            }
            Dim::Spatial => {
                for i in 0..3 {
                    self.a[(row + i, c)] += f[i];
                    self.a[(row + 3 + i, c)] += moment[i];
                }
            }
        }
    }

    /// The joints' force and moment (about `point`, the sensor's marker) on the sensor's
    /// body at its marker, at (q, q̇, q̈); `forces` evaluated there.
    pub(crate) fn reactions_at<K>(
        &mut self,
        query: &K,
        q: &DVector<f64>,
        qd: &DVector<f64>,
        qdd: &DVector<f64>,
        forces: Option<&MarkerForces<M>>,
        point: &Vector3<f64>,
    ) -> (Vector3<f64>, Vector3<f64>)
    where
        K: SensorQuery<Marker = M>,
    {
        let per_body = self.dim.n_rigid();
        for k in 0..self.balances.len() {
            let mut w = self.balances[k].wrench(query, q, qd, qdd);
            if let Some(f) = forces {
                for &s in &self.body_slots[k] {
                    let (r, fk) = f.at(s);
                    w.force -= fk;
                    w.moment -= (r - w.origin).cross(&fk);
                }
            }
            let row = k * per_body;
            match self.dim {
                Dim::Planar => {
                    self.rhs[row] = w.force.x;
                    self.rhs[row + 1] = w.force.y;
                    self.rhs[row + 2] = w.moment.z;
                }
                Dim::Spatial => {
                    for i in 0..3 {
                        self.rhs[row + i] = w.force[i];
                        self.rhs[row + 3 + i] = w.moment[i];
                    }
                }
            }
            self.wrenches[k] = w;
        }
        self.a.fill(0.0);
        let zero = Vector3::zeros();
        for j in 0..self.joints.len() {
            let joint = &self.joints[j];
            let turn = |b: Option<usize>| {
                b.map_or(Matrix3::identity(), |k| {
                    self.wrenches[k].rotation * self.balances[k].start.transpose()
                })
            };
            let [b1, b2] = joint.bodies;
            let t1 = turn(b1);
            let t2 = if b2.is_none() { t1 } else { turn(b2) };
            let (fs, ms) = joint_directions(self.dim, &joint.kind, &t1, &t2, joint.driven);
            let (p2, _) = query.marker_state(&joint.second, q, qd);
            let mut c = joint.first_column;
            for f in fs.as_slice() {
                self.add(c, b2, &p2, f, &zero);
                self.add(c, b1, &p2, &-f, &zero);
                c += 1;
            }
            for m in ms.as_slice() {
                self.add(c, b2, &p2, &zero, m);
                self.add(c, b1, &p2, &zero, &-m);
                c += 1;
            }
        }
        // (AᵀA + ε I) x = Aᵀ W.
        self.normal.gemm_tr(1.0, &self.a, &self.a, 0.0);
        self.x.gemv_tr(1.0, &self.a, &self.rhs, 0.0);
        let n = self.x.len();
        let largest = (0..n).map(|i| self.normal[(i, i)]).fold(0.0, f64::max);
        for i in 0..n {
            self.normal[(i, i)] += 1e-12 * largest;
        }
        cholesky_solve(&mut self.normal, &mut self.x);
        let (mut force, mut moment) = (Vector3::zeros(), Vector3::zeros());
        for j in 0..self.joints.len() {
            let joint = &self.joints[j];
            if joint.sign == 0.0 {
                continue;
            }
            let [b1, b2] = joint.bodies;
            let turn = |b: Option<usize>| {
                b.map_or(Matrix3::identity(), |k| {
                    self.wrenches[k].rotation * self.balances[k].start.transpose()
                })
            };
            let t1 = turn(b1);
            let t2 = if b2.is_none() { t1 } else { turn(b2) };
            let (fs, ms) = joint_directions(self.dim, &joint.kind, &t1, &t2, joint.driven);
            let (p2, _) = query.marker_state(&joint.second, q, qd);
            let mut c = joint.first_column;
            for f in fs.as_slice() {
                let fc = joint.sign * self.x[c] * f;
                force += fc;
                moment += (p2 - point).cross(&fc);
                c += 1;
            }
            for m in ms.as_slice() {
                moment += joint.sign * self.x[c] * m;
                c += 1;
            }
        }
        (force, moment)
    }
}

/// Solve N x = b in place for a symmetric positive definite N (its lower triangle is
/// overwritten by the Cholesky factor L, N = L Lᵀ; `b` by x). A non-positive pivot (a
/// balance with no reactions to solve for) leaves that unknown 0.
fn cholesky_solve(n: &mut DMatrix<f64>, b: &mut DVector<f64>) {
    let size = b.len();
    for j in 0..size {
        let mut d = n[(j, j)];
        for k in 0..j {
            d -= n[(j, k)] * n[(j, k)];
        }
        let d = if d > 0.0 { d.sqrt() } else { f64::INFINITY };
        n[(j, j)] = d;
        for i in j + 1..size {
            let mut s = n[(i, j)];
            for k in 0..j {
                s -= n[(i, k)] * n[(j, k)];
            }
            n[(i, j)] = s / d;
        }
    }
    for i in 0..size {
        let mut s = b[i];
        for k in 0..i {
            s -= n[(i, k)] * b[k];
        }
        b[i] = s / n[(i, i)];
    }
    for i in (0..size).rev() {
        let mut s = b[i];
        for k in i + 1..size {
            s -= n[(k, i)] * b[k];
        }
        b[i] = s / n[(i, i)];
    }
}

#[cfg(test)]
mod tests {
    use super::cholesky_solve;
    use nalgebra::{DMatrix, DVector};

    #[test]
    fn cholesky_solve_solves_a_symmetric_positive_definite_system() {
        let a = DMatrix::from_row_slice(3, 3, &[4.0, 1.0, 0.5, 1.0, 3.0, 0.2, 0.5, 0.2, 2.0]);
        let x = DVector::from_vec(vec![1.0, -2.0, 0.5]);
        let mut b = &a * &x;
        let mut n = a.clone();
        cholesky_solve(&mut n, &mut b);
        assert!((b - x).norm() < 1e-14);
    }
}
