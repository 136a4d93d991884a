//! Every standard scene exported to the file format builds back to the
//! same field, bounds and inside point (bit for bit, in `f64`), and the
//! JSON schema round-trips (parse ∘ print = id).

use boundtrace_cli::scene_format::SceneFile;
use boundtrace_tracer::scenes::{DEFAULT_SEED, NAMES, Scene};

#[test]
fn every_standard_scene_round_trips_exactly() {
    for &name in NAMES {
        let scene = Scene::<f64>::build(name, DEFAULT_SEED).unwrap();
        let file = SceneFile::from_scene(&scene).unwrap();
        let json = file.to_json();
        let parsed = SceneFile::parse(&json).unwrap();
        assert_eq!(parsed, file, "{name}: parse(print(file)) differs");
        assert_eq!(parsed.to_json(), json, "{name}: printing is not stable");
        let back = parsed.build::<f64>().unwrap();
        assert_eq!(back.bounds(), scene.bounds(), "{name}");
        assert_eq!(back.inside_point(), scene.inside_point(), "{name}");
        assert_eq!(back.primitive_count(), scene.primitive_count(), "{name}");
        assert_eq!(
            format!("{:?}", back.field()),
            format!("{:?}", scene.field()),
            "{name}: the rebuilt field differs"
        );
    }
}
