//! Property test of the loader's `--set` path (issue 12): any value — finite, NaN, ±inf,
//! 1e308, 0, negative, a huge count — put into any numeric field of a model through
//! `Scene::apply_sets` never panics; the scene either loads (and then prepares or is refused
//! without a panic) or is refused; a value beyond every bound is always refused, with an
//! error that names the field.

use flexmbd_model::{PreparedScene, Scene};
use proptest::prelude::*;
use serde_json::Value;

const MODELS: [&str; 4] = [
    "double_four_bar.ron",
    "spin_up_beam_2d.ron",
    "floating_platform_3d.ron",
    "double_pendulum_3d.ron",
];

fn load(name: &str) -> Scene {
    let path = format!("{}/../../models/{name}", env!("CARGO_MANIFEST_DIR"));
    Scene::load(&path).unwrap_or_else(|e| panic!("{e}"))
}

/// The `--set` path of every numeric field of `scene` except the solver settings (whose
/// step count is bounded by the run): list items by name where they have one, else by index.
fn numeric_paths(scene: &Scene) -> Vec<String> {
    fn walk(v: &Value, path: &str, out: &mut Vec<String>) {
        let join = |k: &str| {
            if path.is_empty() {
                k.to_string()
            } else {
                format!("{path}.{k}")
            }
        };
        match v {
            Value::Number(_) => out.push(path.to_string()),
            Value::Object(map) => {
                for (k, x) in map {
                    if !(path.is_empty() && k == "solver") {
                        walk(x, &join(k), out);
                    }
                }
            }
            Value::Array(items) => {
                for (i, x) in items.iter().enumerate() {
                    let key = x
                        .get("name")
                        .and_then(Value::as_str)
                        .map_or(i.to_string(), String::from);
                    walk(x, &join(&key), out);
                }
            }
            _ => {}
        }
    }
    let mut out = Vec::new();
    walk(&serde_json::to_value(scene).unwrap(), "", &mut out);
    out
}

/// The field's own name: the last part of the path that is not an index.
fn leaf(path: &str) -> &str {
    path.rsplit('.')
        .find(|p| p.parse::<usize>().is_err())
        .unwrap_or(path)
}

/// Values as a user would type them: special and extreme numbers, counts, plain numbers.
fn value() -> impl Strategy<Value = String> {
    prop_oneof![
        Just("NaN".to_string()),
        Just("inf".to_string()),
        Just("-inf".to_string()),
        Just("1e308".to_string()),
        Just("-1e308".to_string()),
        Just("0".to_string()),
        Just("-1".to_string()),
        Just(u64::MAX.to_string()),
        Just("1e17".to_string()),
        (0u64..100).prop_map(|n| n.to_string()),
        any::<f64>().prop_map(|x| format!("{x:?}")),
        (-10.0f64..10.0).prop_map(|x| format!("{x:?}")),
    ]
}

/// Whether the typed value lies beyond every bound of `flexmbd_fe::bounds` (the widest is
/// 1e15) or is not a finite number.
fn beyond_every_bound(value: &str) -> bool {
    value
        .parse::<f64>()
        .is_ok_and(|x| x.is_nan() || x.abs() > 1e16)
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 400, ..ProptestConfig::default() })]

    #[test]
    fn any_value_set_into_any_field_loads_or_is_refused_naming_it(
        model in 0..MODELS.len(),
        field in any::<prop::sample::Index>(),
        value in value(),
    ) {
        let base = load(MODELS[model]);
        let paths = numeric_paths(&base);
        let path = field.get(&paths).clone();
        let mut scene = base.clone();
        match scene.apply_sets(&[(path.clone(), value.clone())]) {
            Ok(()) => {
                prop_assert!(!beyond_every_bound(&value), "{path}={value} was accepted");
                // Loaded: preparing it (FE reduction, rewrites) may refuse but not panic.
                let _ = PreparedScene::new(&scene);
            }
            Err(e) => {
                let message = e.to_string();
                if beyond_every_bound(&value) {
                    prop_assert!(
                        message.contains(leaf(&path)),
                        "{path}={value}: the error does not name the field: {message}"
                    );
                }
            }
        }
    }
}

#[test]
fn every_model_has_numeric_fields_to_set() {
    for name in MODELS {
        let paths = numeric_paths(&load(name));
        assert!(paths.len() > 10, "{name}: {paths:?}");
        assert!(paths.iter().any(|p| p.starts_with("bodies.")), "{name}");
    }
    let four_bar = numeric_paths(&load("double_four_bar.ron"));
    assert!(four_bar.contains(&"bodies.crank1.markers.A.position.0".to_string()));
    assert!(four_bar.contains(&"gravity.1".to_string()));
}
