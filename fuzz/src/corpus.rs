//! The seed corpus: the scene files of `models/` that the loader accepts as they are
//! (body models are written inside the scenes, so they are mutated with them).

use std::path::{Path, PathBuf};

use flexmbd::model::Scene;

/// One scene file of the corpus.
#[derive(Clone, Debug)]
pub struct SeedScene {
    /// The path it was read from (names it in the reproducers).
    pub path: PathBuf,
    /// Its text.
    pub text: String,
}

/// The `*.ron` files of `dir`, in name order, that [`Scene::load`] accepts; the others
/// (not scenes, or refused) are listed in the returned notes.
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
