//! Cross-crate physics validation of flexmbd. The crate holds no code: its tests (`tests/`)
//! check what no single crate can check alone, so that no crate's tests depend on a crate
//! built on top of it:
//!
//! - `formulations_agree_*`: the absolute (natural-coordinate) and relative (semi-recursive)
//!   formulations integrate the same scene to histories whose difference falls as O(h²) — the
//!   double four-bar, rigid and flexible (docs/scenes.md §1), the floating platform with a
//!   closed loop, and spring–dampers with every sensor kind in 3D;
//! - `stiffening_*`: the geometric-stiffening methods (docs/methods.md §6) through the
//!   `flexmbd` facade — against the ANCF large-deformation reference on the spin-up beam
//!   (docs/scenes.md §5), energy conservation with the strain energy U(y), modal sensors under
//!   FNL2's renumbering, foreshortening FS0 and substructuring.
