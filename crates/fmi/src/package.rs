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

/// The platform an FMU's binary is built for: its folder under `binaries/` in FMI 3.0
/// (`x86_64-linux`, …) and in FMI 2.0 (which names only the desktop platforms `linux64`,
/// `darwin64`, `win64`, …), and its shared library's file name.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Platform {
    /// The FMI 3.0 folder (the standard's §2.5.1.2: `<arch>-<sys>`).
    pub fmi3: &'static str,
    /// The FMI 2.0 folder (`None`: FMI 2.0 has no name for the platform).
    pub fmi2: Option<&'static str>,
    /// The shared library's prefix (`lib`, none on Windows) and extension.
    pub prefix: &'static str,
    /// The shared library's extension (`so`, `dylib`, `dll`).
    pub extension: &'static str,
}

/// The platforms an FMU is made for, by the Rust target triple's architecture and system.
const PLATFORMS: [(&str, &str, Platform); 5] = [
    (
        "x86_64",
        "linux",
        platform("x86_64-linux", Some("linux64"), "lib", "so"),
    ),
    (
        "aarch64",
        "linux",
        platform("aarch64-linux", None, "lib", "so"),
    ),
    (
        "x86_64",
        "darwin",
        platform("x86_64-darwin", Some("darwin64"), "lib", "dylib"),
    ),
    (
        "aarch64",
        "darwin",
        platform("aarch64-darwin", None, "lib", "dylib"),
    ),
    (
        "x86_64",
        "windows",
        platform("x86_64-windows", Some("win64"), "", "dll"),
    ),
];

const fn platform(
    fmi3: &'static str,
    fmi2: Option<&'static str>,
    prefix: &'static str,
    extension: &'static str,
) -> Platform {
    Platform {
        fmi3,
        fmi2,
        prefix,
        extension,
    }
}

impl Platform {
    /// The platform of the machine this runs on; `None` for one the FMU is not made for.
    pub fn host() -> Option<Platform> {
        let os = match std::env::consts::OS {
            "macos" => "darwin",
            os => os,
        };
        Self::find(std::env::consts::ARCH, os)
    }

    /// The platform of a Rust target triple (`aarch64-unknown-linux-gnu`,
    /// `x86_64-pc-windows-msvc`, …): its architecture and its system.
    pub fn of_triple(triple: &str) -> Result<Platform, String> {
        let arch = triple.split('-').next().unwrap_or("");
        let os = ["linux", "darwin", "windows"]
            .into_iter()
            .find(|os| triple.split('-').any(|part| part == *os));
        os.and_then(|os| Self::find(arch, os)).ok_or_else(|| {
            format!(
                "--target {triple}: an FMU is made for x86_64 or aarch64 Linux or macOS, or x86_64 Windows (e.g. aarch64-unknown-linux-gnu)"
            )
        })
    }

    fn find(arch: &str, os: &str) -> Option<Platform> {
        PLATFORMS
            .iter()
            .find(|(a, o, _)| *a == arch && *o == os)
            .map(|(_, _, p)| *p)
    }

    /// The folder of `version` under `binaries/`.
    fn folder(&self, version: Version) -> Result<&'static str, String> {
        match version {
            Version::Fmi3 => Ok(self.fmi3),
            Version::Fmi2 => self.fmi2.ok_or_else(|| {
                format!(
                    "FMI 2.0 has no platform name for {} (write FMI 3.0: --fmi 3)",
                    self.fmi3
                )
            }),
        }
    }

    /// The file name of this crate's shared library for the platform.
    pub fn library_name(&self) -> String {
        format!("{}flexmbd_fmi.{}", self.prefix, self.extension)
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
    let base = scene.base_directory();
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
/// `output`, with `library` (this crate built as a shared library for `platform`: it holds
/// both APIs) as its binary, and the real numbers of the scene at the `--set` paths
/// `parameters` as parameters. The scene is compiled and started once, for its variables.
pub fn write_fmu(
    scene: &Scene,
    output: &Path,
    library: &Path,
    platform: &Platform,
    version: Version,
    parameters: &[String],
) -> Result<(), String> {
    let folder = platform.folder(version)?;
    let extension = platform.extension;
    let binary = std::fs::read(library).map_err(|e| {
        format!(
            "cannot read the FMU library {}: {e} (build it with `cargo build --release -p flexmbd-fmi`, with `--target TRIPLE` for another platform, or name it with --library)",
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
    // Deflate at its fastest level: the library (tens of MB with its line tables) shrinks
    // about fourfold in well under a second.
    let options = SimpleFileOptions::default()
        .compression_method(zip::CompressionMethod::Deflated)
        .compression_level(Some(1))
        .unix_permissions(0o644);
    let mut add = |name: &str, bytes: &[u8]| -> Result<(), String> {
        zip.start_file(name, options)
            .and_then(|()| zip.write_all(bytes).map_err(Into::into))
            .map_err(|e| format!("cannot write {name} into {}: {e}", output.display()))
    };
    add("modelDescription.xml", description.as_bytes())?;
    add(&format!("binaries/{folder}/{id}.{extension}"), &binary)?;
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_target_triple_names_its_fmi_folders_and_library() {
        let linux_arm = Platform::of_triple("aarch64-unknown-linux-gnu").unwrap();
        assert_eq!(linux_arm.folder(Version::Fmi3), Ok("aarch64-linux"));
        assert!(
            linux_arm
                .folder(Version::Fmi2)
                .unwrap_err()
                .contains("--fmi 3")
        );
        assert_eq!(linux_arm.library_name(), "libflexmbd_fmi.so");
        let windows = Platform::of_triple("x86_64-pc-windows-msvc").unwrap();
        assert_eq!(windows.folder(Version::Fmi2), Ok("win64"));
        assert_eq!(windows.library_name(), "flexmbd_fmi.dll");
        let mac = Platform::of_triple("aarch64-apple-darwin").unwrap();
        assert_eq!(
            (mac.folder(Version::Fmi3), mac.extension),
            (Ok("aarch64-darwin"), "dylib")
        );
        assert_eq!(
            Platform::of_triple("x86_64-unknown-linux-musl"),
            Platform::of_triple("x86_64-unknown-linux-gnu")
        );
        for refused in [
            "riscv64gc-unknown-linux-gnu",
            "wasm32-unknown-unknown",
            "linux",
            "",
        ] {
            let e = Platform::of_triple(refused).unwrap_err();
            assert!(e.contains(refused) && e.contains("aarch64"), "{e}");
        }
    }

    #[test]
    fn the_host_is_the_platform_of_its_own_triple() {
        if cfg!(all(target_arch = "x86_64", target_os = "linux")) {
            assert_eq!(
                Platform::host(),
                Platform::of_triple("x86_64-unknown-linux-gnu").ok()
            );
        }
    }
}
