//! Every scene in `models/` runs in both formulations (issue 5: "`flexmbd simulate …
//! --formulation relative` works for every scene in `models/`"): a few steps each, status
//! finished and finite sensors. Body-model files (`flexmbd modes` input) are recognised
//! and skipped.

use flexmbd::model::{FormulationKind, Scene};
use flexmbd::simulation::run;

#[test]
fn every_scene_runs_in_both_formulations() {
    let dir = concat!(env!("CARGO_MANIFEST_DIR"), "/../../models");
    let mut files: Vec<_> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|x| x == "ron"))
        .collect();
    files.sort();
    let mut scenes = 0;
    for path in files {
        let text = std::fs::read_to_string(&path).unwrap();
        let name = path.display().to_string();
        let mut scene = match Scene::from_ron_str(&text, &name) {
            Ok(s) => s,
            Err(e) => {
                assert!(
                    flexmbd::inventory::BodyModelFile::parse(&text, &path).is_ok(),
                    "{name} is neither a scene nor a body model: {e}"
                );
                continue;
            }
        };
        scenes += 1;
        scene.solver.duration = 10.0 * scene.solver.step;
        scene.solver.output_interval = None;
        for f in [FormulationKind::Absolute, FormulationKind::Relative] {
            scene.solver.formulation = f;
            let (summary, h) = run(&scene, |_| {}).unwrap_or_else(|e| panic!("{name} {f:?}: {e}"));
            assert_eq!(summary.status, "ok", "{name} {f:?}: {:?}", summary.message);
            assert_eq!(summary.steps, 10, "{name} {f:?}");
            for row in &h.rows {
                assert!(row.iter().all(|v| v.is_finite()), "{name} {f:?}: {row:?}");
            }
        }
    }
    assert!(scenes >= 8, "{scenes} scenes found");
}
