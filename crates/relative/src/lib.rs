//! The semi-recursive relative-coordinate formulation of flexmbd (docs/methods.md §4;
//! García de Jalón et al. 2005; the flexible extension of Lugrís's thesis, ch. 2).
//!
//! **Coordinates** (§4.4): z = the elementary-joint coordinates of a spanning tree of
//! the joints, then every flexible body's modal coordinates y (static modes first).
//! A rigid body is the zero-mode case. Joint coordinates are measured from the scene's
//! t = 0 placement, so z(0) = 0 for them.
//!
//! **Velocities** (§4.1): every body k has Z_k = {ṡ_k; ω_k; ẏ_k}, with ṡ_k the velocity
//! of the body point at the global origin. Along the augmented tree (see
//! [`topology`]), an elementary joint e moves its frame by its twist,
//! Z^r_next = Z^r_f + v_e ė, and D_next = D_f + d_e with (§4.2)
//!
//! ```text
//! revolute about a through p:  v = {p × a; a},  d = {(ṗ × a + p × (ω_f × a)) ė; (ω_f × a) ė}
//! prismatic along a:           v = {a; 0},      d = {(ω_f × a) ė; 0}
//! ```
//!
//! and the static modes of a parent node P are prismatic (translations) and revolute
//! (rotations) elementary joints of the node frame (§4.3); a Buckens child hung at a node
//! that moves with its own modes gets the inverse chain, the same joints with rates −X_Q ẏ
//! of its own modes between the joint frame and its frame ([`topology`]). Each elementary joint's
//! rate is a constant combination of ż, ė = L_e ż (a joint coordinate, or X_P rows
//! times ẏ), so Z = R_w w, w = L ż, with R_w the §4.4 matrix of one twist per
//! elementary joint and one owner per modal coordinate; R is never formed.
//!
//! **Dynamics** (§4.5, §2.4, §2.6): body terms M̄_k, Q̄_k in the s form from
//! `flexmbd-body` (inertia by either [`flexmbd_body::InertiaMethod`], gravity, elastic
//! forces); P_k = Q̄_k − M̄_k {D_k; 0}; 𝕄_F, ℙ_F accumulated leaves → root; then
//!
//! ```text
//! M_w[a, e] = v_aᵀ 𝕄_{F(e)} v_e        (a on the path of e)
//! M_w[a, m] = v_aᵀ (M̄^ry_k)_{:,m}       (a moves body k, m a mode of k)
//! M_w[m, m'] = (M̄^yy_k)_{mm'},  Q_w[e] = v_eᵀ ℙ_{F(e)},  Q_w[m] = (P^y_k)_m
//! M = Lᵀ M_w L,  Q = Lᵀ Q_w
//! ```
//!
//! so M = Rᵀ M̄ R and Q = Rᵀ (Q̄ − M̄ Ṙ ż). Tangents (§4.6): K ≈ blockdiag K_ff,
//! C ≈ blockdiag C_ff on the modal coordinates.
//!
//! **Constraints** (§4.6): cut joints give Φ in the Cartesian positions of their two
//! markers (point coincidence r_i − r_j; 2D angle sin(ψ − ψ₀); perpendicularity a·b;
//! sliding n·(r_j − r_i)), with Φ_z = Σ_k Φ_{Z_k} R_k (walk from each body to the root)
//! and c = Σ_k Φ_{Z_k} {D_k; 0} + the Cartesian velocity-product terms + Φ̇_t. A driven
//! tree joint adds z_c − θ(t), a row the integrator may do without: the coordinate is
//! declared driven (`Formulation::driven_coordinates`) and `flexmbd_core::DrivenEliminated`
//! takes it out of the unknowns. A driven planar cut revolute adds the angle form. The
//! scene's constraints between markers (docs/methods.md §3.4) are never tree edges: a
//! `Distance` adds ½(|r_j − r_i|² − L²), a `PointInPlane` the sliding row with n fixed in
//! body 1.
//! Redundant closure equations are kept (ALI3-P tolerates them).
//!
//! **Initial conditions**: z(0) from the placements (joint coordinates 0, modes from
//! `initial_modes`); ż(0) by the kinetic-energy-weighted least-squares fit of the
//! scene's body velocities, M ż = Σ R_kᵀ M̄_k Z*_k. The integrator makes both consistent.

// Compiling a scene: `build` (in named steps), `cut_joints` (the constraints of the cut
// joints and drivers), `initial_state`, on `topology` (the augmented tree). The pass:
// `system` (the storage and the `Formulation` pass), `kinematics` (§4.5 steps 1–3),
// `body_kernels` (step 4: rigid in closed form, flexible), `dynamics` (steps 4–7),
// `constraints` (§4.6), `marker_kinematics` (the force elements' query). Outputs: `sensors`,
// `inspection`.
mod body_kernels;
mod build;
mod constraints;
mod cut_joints;
mod dynamics;
mod initial_state;
mod inspection;
mod kinematics;
mod layout;
mod marker_kinematics;
mod marker_table;
mod pattern;
mod sensors;
mod system;
pub mod topology;

pub use system::Relative;

use flexmbd_model::{ModelError, PreparedScene};

/// Compile a prepared scene (planar or spatial) for the relative formulation.
///
/// The scene must be prepared first ([`PreparedScene::new`]: validated, rewritten for its
/// stiffening method, its bodies reduced and built, its names resolved):
///
/// ```
/// use flexmbd_core::Formulation;
/// use flexmbd_model::{PreparedScene, Scene};
/// let path = concat!(env!("CARGO_MANIFEST_DIR"), "/../../models/double_four_bar.ron");
/// let scene = Scene::load(path)?;
/// let formulation = flexmbd_relative::compile(&PreparedScene::new(&scene)?)?;
/// assert!(formulation.n_coordinates() > 0);
/// # Ok::<(), flexmbd_model::ModelError>(())
/// ```
///
/// A bare scene is not accepted, so no formulation can run a scene whose stiffening rewrite
/// (FNL2's axial basis, substructuring) was skipped:
///
/// ```compile_fail
/// use flexmbd_model::Scene;
/// let path = concat!(env!("CARGO_MANIFEST_DIR"), "/../../models/double_four_bar.ron");
/// let scene = Scene::load(path)?;
/// let formulation = flexmbd_relative::compile(&scene)?;
/// # Ok::<(), flexmbd_model::ModelError>(())
/// ```
pub fn compile(prepared: &PreparedScene) -> Result<Relative, ModelError> {
    Relative::compile(prepared)
}
