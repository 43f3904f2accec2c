//! A scene file, read exactly as `stickslip simulate --scene FILE` reads it:
//! `stickslip_cli::scene_args::SceneArgs::scene`, i.e. `Scene::load` (read the file,
//! parse by extension, check every field). The bytes go to a scratch file whose
//! extension is `.json` when the first non-blank byte is `{` and `.toml` otherwise.
//!
//! A scene that passes is then used: written as JSON and read back, and, when its model
//! is small (see `stickslip_fuzz::cheap_to_build`) and it uses no weights file, built
//! into a simulation with its friction law and stepped a few times.
//!
//! Checked properties (a panic is a finding):
//! - nothing panics, whatever the bytes;
//! - a checked scene written as JSON reads back to the same scene;
//! - a checked scene builds (the check promises that everything downstream works on
//!   it): building may fail only with an error, never a panic.

#![no_main]

use libfuzzer_sys::fuzz_target;
use stickslip::law_source::LawSource;
use stickslip::scene::Scene;
use stickslip::simulation::Simulator;
use stickslip_cli::scene_args::SceneArgs;
use stickslip_fuzz::{cheap_to_build, scratch_file};

fuzz_target!(|data: &[u8]| {
    let json = data
        .iter()
        .find(|b| !b.is_ascii_whitespace())
        .is_some_and(|&b| b == b'{');
    let path = scratch_file("scene", if json { "json" } else { "toml" });
    std::fs::write(&path, data).expect("cannot write the scratch scene file");
    let args = SceneArgs {
        scene: Some(path),
        ..SceneArgs::default()
    };
    let Ok(checked) = args.scene() else {
        return;
    };

    let text = serde_json::to_string(checked.scene()).expect("a scene serialises");
    let back = Scene::from_json_str(&text)
        .unwrap_or_else(|e| panic!("a checked scene written as JSON does not read back: {e}"));
    assert_eq!(&back, checked.scene(), "JSON round trip changed the scene");

    if checked.friction.weights.is_some() || !cheap_to_build(&checked) {
        return;
    }
    // As a stand-alone run: external is refused (only the FMU has its inputs).
    let Ok(source) = LawSource::resolve(&checked) else {
        return;
    };
    if source.is_external() {
        return;
    }
    let Ok(law) = source.law() else {
        return;
    };
    let Ok(mut simulator) = Simulator::new(checked, law) else {
        return;
    };
    for _ in 0..5 {
        if simulator.step().is_err() {
            break;
        }
    }
});
