//! Property test: the shipped scenes, mutated as a careless or hostile user would (a field
//! deleted, duplicated into another table, or replaced by a value of another type or an
//! extreme number: subnormals, NaN, ±inf, ±0, huge integers), go through parse, validation
//! and, when accepted and small enough, construction and the first step of every method.
//! Never a panic; never longer than a bound; an accepted scene steps to finite fields.
use impact::study::{Overrides, Study};
use impact_core::method::MethodKind;
use impact_core::Scene;
use proptest::prelude::*;
use std::time::{Duration, Instant};
use toml::Value;

/// Largest work (points) a mutated scene may build and step here.
const MAX_POINTS_STEPPED: f64 = 2e5;

fn leaf_paths(value: &Value, prefix: &mut Vec<String>, out: &mut Vec<Vec<String>>) {
    if let Value::Table(table) = value {
        for (key, child) in table {
            prefix.push(key.clone());
            out.push(prefix.clone());
            leaf_paths(child, prefix, out);
            prefix.pop();
        }
    }
}

fn get_mut<'a>(root: &'a mut Value, path: &[String]) -> Option<&'a mut Value> {
    path.iter()
        .try_fold(root, |v, key| v.as_table_mut()?.get_mut(key))
}

fn replacement(kind: u8, number: f64) -> Value {
    match kind % 8 {
        0 => Value::Float(number),
        1 => Value::Integer(number as i64),
        2 => Value::String(format!("{number}")),
        3 => Value::Boolean(number > 0.0),
        4 => Value::Array(vec![Value::Float(number), Value::Float(-number)]),
        5 => Value::Array(vec![]),
        6 => Value::Integer(i64::MAX),
        _ => Value::Table(Default::default()),
    }
}

fn extreme() -> impl Strategy<Value = f64> {
    prop_oneof![
        Just(f64::NAN),
        Just(f64::INFINITY),
        Just(f64::NEG_INFINITY),
        Just(0.0),
        Just(-0.0),
        Just(f64::MIN_POSITIVE / 4.0),
        Just(5e-324),
        Just(f64::MAX),
        Just(1e300),
        Just(1e-300),
        Just(-1.0),
        Just(1e30),
        Just(1e-30),
        any::<f64>(),
        -1e6..1e6f64,
    ]
}

/// Parse, validate and, if accepted and small, build and step every method once.
fn exercise(text: &str) {
    let Ok(scene) = Scene::parse_toml(text, "mutated.toml") else {
        return;
    };
    exercise_study(scene, Overrides::default());
}

/// Validate `scene` with `overrides` and, if accepted and small, step every method once.
fn exercise_study(scene: Scene, overrides: Overrides) {
    let Ok(study) = Study::new(scene, overrides) else {
        return;
    };
    if study.check_work(&MethodKind::ALL).is_err() {
        return;
    }
    let points: f64 = study
        .scene
        .domain
        .cells
        .iter()
        .map(|&n| n as f64)
        .product::<f64>()
        * study.scene.domain.points_per_cell as f64;
    if points > MAX_POINTS_STEPPED {
        return;
    }
    match study.dim() {
        1 => step_all::<1>(&study),
        2 => step_all::<2>(&study),
        _ => step_all::<3>(&study),
    }
}

fn step_all<const D: usize>(study: &Study) {
    let problem = study
        .problem::<D>()
        .expect("a validated scene builds its problem");
    for kind in MethodKind::ALL {
        let Ok(mut method) = impact::build(&problem, study.config(kind)) else {
            continue;
        };
        let dt = method.stable_dt();
        assert!(dt.is_finite() && dt > 0.0, "{kind}: dt = {dt}");
        method.step(0.0, dt.min(problem.t_end));
        assert!(method.energy().is_finite(), "{kind}: energy after one step");
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 300, ..ProptestConfig::default() })]

    #[test]
    fn mutated_scenes_never_panic_or_hang(
        scene in 0usize..impact_core::scene::BUILTIN.len(),
        pick in any::<prop::sample::Index>(),
        target in any::<prop::sample::Index>(),
        action in 0u8..4,
        kind in any::<u8>(),
        number in extreme(),
    ) {
        let name = impact_core::scene::BUILTIN[scene];
        let text = impact_core::scene::builtin(name).expect("shipped");
        let mut value: Value = text.parse().expect("shipped scenes are TOML");
        let mut paths = Vec::new();
        leaf_paths(&value, &mut Vec::new(), &mut paths);
        let path = pick.get(&paths).clone();
        match action {
            // delete the field
            0 => {
                let (last, parent) = path.split_last().expect("non-empty path");
                if let Some(Value::Table(t)) = get_mut(&mut value, parent) {
                    t.remove(last);
                }
            }
            // duplicate it into another table
            1 => {
                let copy = get_mut(&mut value, &path).cloned();
                let other = target.get(&paths).clone();
                if let (Some(copy), Some(Value::Table(t))) = (copy, get_mut(&mut value, &other)) {
                    t.insert(path.last().expect("non-empty").clone(), copy);
                }
            }
            // replace it by another type or an extreme number
            _ => {
                if let Some(v) = get_mut(&mut value, &path) {
                    *v = replacement(kind, number);
                }
            }
        }
        // TOML has no NaN/inf in this writer's output for some values: write by hand
        let text = toml::to_string(&value).unwrap_or_else(|_| text.to_string());
        let start = Instant::now();
        exercise(&text);
        prop_assert!(start.elapsed() < Duration::from_secs(20), "took {:?}", start.elapsed());
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 200, ..ProptestConfig::default() })]

    /// The command-line overrides with extreme values: the same guarantees.
    #[test]
    fn extreme_overrides_never_panic_or_hang(
        scene in 0usize..impact_core::scene::BUILTIN.len(),
        cells in prop_oneof![Just(None), Just(Some(0usize)), Just(Some(usize::MAX)), (1usize..400).prop_map(Some)],
        points_per_cell in prop_oneof![Just(None), (0usize..70).prop_map(Some), Just(Some(usize::MAX))],
        courant in prop::option::of(extreme()),
        t_end in prop::option::of(extreme()),
        load in prop::option::of(extreme()),
        times in prop::option::of(prop::collection::vec(extreme(), 0..4)),
    ) {
        let name = impact_core::scene::BUILTIN[scene];
        let parsed = Scene::builtin(name).expect("shipped");
        let overrides = Overrides {
            cells,
            points_per_cell,
            courant,
            t_end,
            load_magnitude: load,
            output_times: times,
            ..Overrides::default()
        };
        let start = Instant::now();
        exercise_study(parsed, overrides);
        prop_assert!(start.elapsed() < Duration::from_secs(20), "took {:?}", start.elapsed());
    }
}
