//! The self-contained web page of a [`Recording`]: the glTF binary embedded (base64) with
//! three.js r147 and its `GLTFLoader` and `OrbitControls` (vendored in `vendor/three/`,
//! MIT, its LICENSE beside them; r147 is the last release shipping them as plain scripts,
//! so the page needs no module loader and opens offline from a file), and a player:
//! play/pause, time slider, speed, deformation scale, orbit camera, a chart of one sensor
//! whose cursor follows the time. It opens playing; `page.html#t=1.5` opens paused at
//! t = 1.5 s. `window.flexmbd.project([x, y, z])` gives the page pixel where a ground point
//! is drawn (for tests).

use base64::Engine as _;

use crate::record::Recording;

// The vendored scripts go in as they are: none holds `</script` or `<!--`, which would end
// their `<script>` element early (tested below).
const TEMPLATE: &str = include_str!("page.html");
const THREE: &str = include_str!("../vendor/three/three.min.js");
const GLTF_LOADER: &str = include_str!("../vendor/three/GLTFLoader.js");
const ORBIT_CONTROLS: &str = include_str!("../vendor/three/OrbitControls.js");

/// The page of `recording` around its `glb`; `up` is the direction drawn upwards (against
/// gravity), `view` the direction from the scene to the camera.
pub fn html(recording: &Recording, glb: &[u8], up: [f64; 3], view: [f64; 3]) -> String {
    let data = serde_json::json!({
        "up": up,
        "view": view,
        "sensors": recording.sensor_names,
        "times": recording.times,
        "values": recording.sensors,
        "interrupted": recording.interrupted,
        "failure": recording.failure.as_ref().map(|(t, message)| serde_json::json!({ "t": t, "message": message })),
    });
    let glb = base64::engine::general_purpose::STANDARD.encode(glb);
    let mut page = String::with_capacity(TEMPLATE.len() + THREE.len() + glb.len() + 200_000);
    let mut rest = TEMPLATE;
    while let Some(start) = rest.find("@@") {
        page.push_str(&rest[..start]);
        let after = &rest[start + 2..];
        let end = after
            .find("@@")
            .expect("page.html: placeholders are closed");
        match &after[..end] {
            "TITLE" => page.push_str(&escape(&recording.scene)),
            "THREE" => page.push_str(THREE),
            "GLTFLOADER" => page.push_str(GLTF_LOADER),
            "ORBITCONTROLS" => page.push_str(ORBIT_CONTROLS),
            // `<` as \u003c: no sensor name can end the script element.
            "DATA" => page.push_str(&data.to_string().replace('<', "\\u003c")),
            "GLB" => page.push_str(&glb),
            other => panic!("page.html: unknown placeholder {other}"),
        }
        rest = &after[end + 2..];
    }
    page.push_str(rest);
    page
}

/// Text safe in HTML.
fn escape(text: &str) -> String {
    text.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
}

#[cfg(test)]
mod tests {
    #[test]
    fn the_vendored_scripts_do_not_end_their_script_element() {
        for text in [super::THREE, super::GLTF_LOADER, super::ORBIT_CONTROLS] {
            let lower = text.to_ascii_lowercase();
            assert!(!lower.contains("</script") && !lower.contains("<!--"));
        }
    }
}
