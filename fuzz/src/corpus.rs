//! The seed corpus: the scene files of `models/` that the loader accepts as they are
//! (body models are written inside the scenes, so they are mutated with them).

use std::path::{Path, PathBuf};

use flexmbd::model::{BodyModel, Scene};

/// One scene file of the corpus.
#[derive(Clone, Debug)]
pub struct SeedScene {
    /// The path it was read from (names it in the reproducers).
    pub path: PathBuf,
    /// Its text.
    pub text: String,
}

/// Scenes whose imported FE exports exceed this many bytes are left out: every mutant would
/// spend its time reading them (the rotor's 7 MB take half a second), past the time cap;
/// the readers are fuzzed on small exports by the reader campaign (`--target readers`).
pub const MAX_EXPORT_BYTES: u64 = 1 << 20;

/// The bytes of the FE exports a scene's imported bodies read (paths relative to `dir`).
fn export_bytes(scene: &Scene, dir: &Path) -> u64 {
    scene
        .bodies
        .iter()
        .filter_map(|b| match &b.model {
            BodyModel::Imported(spec) => Some(spec.source.paths()),
            _ => None,
        })
        .flatten()
        .filter_map(|p| std::fs::metadata(dir.join(p)).ok())
        .map(|m| m.len())
        .sum()
}

/// The `*.ron` files of `dir`, in name order, that [`Scene::load`] accepts and whose FE
/// exports are small ([`MAX_EXPORT_BYTES`]); the others are listed in the returned notes.
pub fn load_corpus(dir: &Path) -> Result<(Vec<SeedScene>, Vec<String>), String> {
    let entries =
        std::fs::read_dir(dir).map_err(|e| format!("cannot read {}: {e}", dir.display()))?;
    let mut paths: Vec<PathBuf> = entries
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|x| x == "ron"))
        .collect();
    paths.sort();
    let mut seeds = Vec::new();
    let mut skipped = Vec::new();
    for path in paths {
        match Scene::load(&path) {
            Ok(scene) if export_bytes(&scene, dir) > MAX_EXPORT_BYTES => {
                skipped.push(format!(
                    "{} skipped, its FE exports are {:.1} MB (over {} MB): the readers are fuzzed \
                     on small exports (--target readers)",
                    path.display(),
                    export_bytes(&scene, dir) as f64 / 1e6,
                    MAX_EXPORT_BYTES >> 20
                ));
            }
            Ok(_) => {
                let text = std::fs::read_to_string(&path)
                    .map_err(|e| format!("cannot read {}: {e}", path.display()))?;
                seeds.push(SeedScene { path, text });
            }
            Err(e) => {
                let why: String = e.to_string().chars().take(120).collect();
                skipped.push(format!("{} skipped, not a scene: {why}…", path.display()));
            }
        }
    }
    if seeds.is_empty() {
        return Err(format!(
            "no scene in {} loads: nothing to mutate",
            dir.display()
        ));
    }
    Ok((seeds, skipped))
}

/// The workspace's `models/` directory (the default corpus).
pub fn default_models_dir() -> PathBuf {
    workspace_root().join("models")
}

/// The workspace root (the parent of this crate's directory).
pub fn workspace_root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .parent()
        .expect("the fuzz crate lives in the workspace root")
        .to_path_buf()
}
