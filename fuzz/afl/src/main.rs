//! AFL++ target for the scene loader: every input that is UTF-8 is parsed as a scene
//! ([`Scene::from_ron_str`]) and, when it parses, validated. A panic, an abort or a hang
//! in either is what AFL++ reports as a crash or a hang; a refusal is a normal outcome.

use flexmbd_model::Scene;

fn main() {
    afl::fuzz!(|data: &[u8]| {
        if let Ok(text) = std::str::from_utf8(data)
            && let Ok(scene) = Scene::from_ron_str(text, "afl-input.ron")
        {
            let _ = scene.validate();
        }
    });
}
