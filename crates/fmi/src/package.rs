//! The FMU archive of a scene: `modelDescription.xml`, the shared library of this crate
//! in `binaries/PLATFORM/IDENTIFIER.so`, and in `resources/` the scene (`scene.ron`, the
//! scene as given with its `--set` values applied) and every file it reads (an imported
//! body's FE export), copied to `resources/data/` and named there, so the FMU runs from
//! any folder. The scene written is read back and compared with the one given: the FMU
//! runs exactly the scene `flexmbd simulate` would.

use std::io::Write as _;
use std::path::{Path, PathBuf};

use flexmbd::Simulation;
use flexmbd::model::{BodyModel, Scene};
use zip::write::SimpleFileOptions;

use crate::instance::{PARAMETERS_FILE, SCENE_FILE, token};
use crate::model_description;
use crate::variables::Variables;

/// The FMI version of an FMU.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Version {
    /// FMI 2.0.
    Fmi2,
    /// FMI 3.0.
    Fmi3,
}

/// The FMI 3.0 platform folder of the machine this runs on, and its shared-library
/// extension; `None` for a platform the FMU is not made for.
pub fn host_platform() -> Option<(&'static str, &'static str)> {
    match (std::env::consts::ARCH, std::env::consts::OS) {
        ("x86_64", "linux") => Some(("x86_64-linux", "so")),
        ("aarch64", "linux") => Some(("aarch64-linux", "so")),
        ("x86_64", "macos") => Some(("x86_64-darwin", "dylib")),
        ("aarch64", "macos") => Some(("aarch64-darwin", "dylib")),
        ("x86_64", "windows") => Some(("x86_64-windows", "dll")),
        _ => None,
    }
}

/// The platform folder of `version` for the machine this runs on (FMI 2.0 names only
/// the 64-bit desktop platforms: linux64, darwin64, win64).
fn platform_folder(version: Version) -> Option<&'static str> {
    let (fmi3, _) = host_platform()?;
    match version {
        Version::Fmi3 => Some(fmi3),
        Version::Fmi2 => match fmi3 {
            "x86_64-linux" => Some("linux64"),
            "x86_64-darwin" => Some("darwin64"),
            "x86_64-windows" => Some("win64"),
            _ => None,
        },
    }
}

/// The model identifier of the FMU written to `output`: its file stem, every character
/// that is not an ASCII letter, digit or `_` made `_`, and a leading digit prefixed.
pub fn identifier(output: &Path) -> String {
    let stem = output
        .file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_default();
    let mut id: String = stem
        .chars()
        .map(|c| if c.is_ascii_alphanumeric() { c } else { '_' })
        .collect();
    if !id.starts_with(|c: char| c.is_ascii_alphabetic()) {
        id.insert_str(0, "fmu_");
    }
    id
}

/// The scene as the FMU holds it: its text, and the files it reads (path in the archive,
/// file on disk).
pub struct Resources {
    /// `resources/scene.ron`.
    pub scene_text: String,
    /// (`resources/data/…`, the file it is copied from).
    pub files: Vec<(String, PathBuf)>,
}

/// The scene's text for `resources/scene.ron`, with each imported body's files renamed
/// to `data/K_NAME` (K counts the files), and those files. The text is read back and must
/// give `scene` again.
pub fn resources(scene: &Scene) -> Result<Resources, String> {
    let origin = Path::new(&scene.origin);
    let base = match origin.parent() {
        Some(dir) if origin.is_file() => dir.to_path_buf(),
        _ => PathBuf::from("."),
    };
    let mut shipped = scene.clone();
    let mut files = Vec::new();
    for body in &mut shipped.bodies {
        if let BodyModel::Imported(spec) = &mut body.model {
            for path in spec.source.paths_mut() {
                let name = path
                    .file_name()
                    .map(|n| n.to_string_lossy().into_owned())
                    .unwrap_or_else(|| "file".into());
                let renamed = format!("data/{}_{name}", files.len());
                files.push((format!("resources/{renamed}"), base.join(&*path)));
                *path = PathBuf::from(renamed);
            }
        }
    }
    let scene_text = ron::ser::to_string_pretty(&shipped, ron::ser::PrettyConfig::default())
        .map_err(|e| format!("cannot write the scene as RON: {e}"))?;
    let mut read_back = Scene::from_ron_str(&scene_text, SCENE_FILE)
        .map_err(|e| format!("the scene written for the FMU does not read back: {e}"))?;
    read_back.origin.clone_from(&shipped.origin);
    read_back.source.clone_from(&shipped.source);
    for (a, b) in read_back.bodies.iter_mut().zip(&shipped.bodies) {
        if let (BodyModel::Beam(a), BodyModel::Beam(b)) = (&mut a.model, &b.model) {
            a.origin.clone_from(&b.origin);
        }
    }
    if read_back != shipped {
        return Err("the scene written for the FMU reads back different (a defect)".into());
    }
    Ok(Resources { scene_text, files })
}

/// Write the FMI `version` co-simulation FMU of `scene` (validated; `origin` its file) to
/// `output`, with `library` (this crate built as a shared library for the host: it holds
/// both APIs) as its binary, and the real numbers of the scene at the `--set` paths
/// `parameters` as parameters. The scene is compiled and started once, for its variables.
pub fn write_fmu(
    scene: &Scene,
    output: &Path,
    library: &Path,
    version: Version,
    parameters: &[String],
) -> Result<(), String> {
    let platform = platform_folder(version);
    let (platform, extension) = host_platform()
        .zip(platform)
        .map(|((_, extension), platform)| (platform, extension))
        .ok_or_else(|| {
            format!(
                "no FMI {version:?} platform name for {}-{}",
                std::env::consts::ARCH,
                std::env::consts::OS
            )
        })?;
    let binary = std::fs::read(library).map_err(|e| {
        format!(
            "cannot read the FMU library {}: {e} (build it with `cargo build --release -p flexmbd-fmi`, or name it with --library)",
            library.display()
        )
    })?;
    let resources = resources(scene)?;
    let simulation = Simulation::new(scene).map_err(|e| e.to_string())?;
    let variables = Variables::of(&simulation, scene, parameters)?;
    let id = identifier(output);
    let token = token(&resources.scene_text, parameters);
    let description = match version {
        Version::Fmi3 => model_description::fmi3(scene, &variables, &id, &token),
        Version::Fmi2 => model_description::fmi2(scene, &variables, &id, &token),
    };
    let file = std::fs::File::create(output)
        .map_err(|e| format!("cannot create {}: {e}", output.display()))?;
    let mut zip = zip::ZipWriter::new(file);
    let options = SimpleFileOptions::default()
        .compression_method(zip::CompressionMethod::Stored)
        .unix_permissions(0o644);
    let mut add = |name: &str, bytes: &[u8]| -> Result<(), String> {
        zip.start_file(name, options)
            .and_then(|()| zip.write_all(bytes).map_err(Into::into))
            .map_err(|e| format!("cannot write {name} into {}: {e}", output.display()))
    };
    add("modelDescription.xml", description.as_bytes())?;
    add(&format!("binaries/{platform}/{id}.{extension}"), &binary)?;
    add(
        &format!("resources/{SCENE_FILE}"),
        resources.scene_text.as_bytes(),
    )?;
    if !parameters.is_empty() {
        let list: String = parameters.iter().map(|p| format!("{p}\n")).collect();
        add(&format!("resources/{PARAMETERS_FILE}"), list.as_bytes())?;
    }
    for (name, path) in &resources.files {
        let bytes = std::fs::read(path)
            .map_err(|e| format!("cannot read {} (the scene reads it): {e}", path.display()))?;
        add(name, &bytes)?;
    }
    zip.finish()
        .map_err(|e| format!("cannot finish {}: {e}", output.display()))?;
    Ok(())
}
