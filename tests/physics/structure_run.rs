//! Stick-slip on a user's structure (issue 35 item 2, the full model): the paper scene
//! on the CalculiX beam (examples/calculix-beam/scene.toml: the committed ccx files,
//! friction at the mid-height node of the free end) against the built-in plane stress at
//! the same mesh (100 x 1 Q8, the deck's nodes) with its tip moved to that same node.
//!
//! Tolerance 0.5 % on breakaway, period and the tip corridor (issue 35's promise for the
//! full model). What separates the two is the files' 14 digits: the static tip differs
//! by 8.3e-5 and f1 by 4.3e-5 (calculix_beam.rs), and the run by one step at most in
//! breakaway (1e-4 s of 0.4 s, 2.5e-4). The contact point is part of the comparison:
//! the built-in model's own tip (the end face's mean, Simpson weights) is a different
//! observation, so the reference uses the mid node too.

use std::path::{Path, PathBuf};
use stickslip::law_source::LawSource;
use stickslip::metrics::Summary;
use stickslip::run::run_scene;
use stickslip::scene::{CheckedScene, Scene};
use stickslip::simulation::Simulator;
use stickslip::structure::StructuralModel;

fn example() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../examples/calculix-beam")
}

/// The example scene as the command line loads it (paths relative to the scene file).
fn calculix_scene() -> CheckedScene {
    Scene::load(&example().join("scene.toml")).unwrap()
}

/// The built-in plane stress of the paper scene (100 x 1 Q8, the deck's mesh) observed
/// and loaded at the end face's mid node in y, as the example's contact (node 502).
fn built_in_at_mid_node(scene: &CheckedScene) -> StructuralModel {
    let mut model = StructuralModel::plane_stress(scene, scene.fidelity.element_size);
    // The face's three nodes carry Simpson weights 1/6, 4/6, 1/6: the mid node is the
    // heaviest.
    let &(mid, weight) = model.tip.iter().max_by(|a, b| a.1.total_cmp(&b.1)).unwrap();
    assert!((weight - 4.0 / 6.0).abs() < 1e-12, "{:?}", model.tip);
    model.tip = vec![(mid, 1.0)];
    model
}

fn summary_on(scene: CheckedScene, model: StructuralModel) -> Summary {
    let law = LawSource::resolve(&scene).unwrap().law().unwrap();
    let mut sim = Simulator::with_model(scene, model, law).unwrap();
    sim.keep_all_transitions();
    let samples = sim.run(1).unwrap();
    Summary::new(&samples, sim.transitions())
}

fn within(what: &str, a: f64, b: f64, tolerance: f64) {
    let relative = (a - b) / b;
    println!("{what}: CalculiX {a:.6e}, built-in {b:.6e}, relative {relative:+.2e}");
    assert!(relative.abs() < tolerance, "{what}: {a} vs {b}");
}

#[test]
fn the_paper_scene_on_the_calculix_beam_matches_the_built_in_plane_stress() {
    let scene = calculix_scene();
    let model = StructuralModel::build(&scene).unwrap();
    assert_eq!(model.dofs(), 1002);
    assert!(model.label.contains("calculix beam"), "{}", model.label);
    let paper = CheckedScene::paper();
    let reference = built_in_at_mid_node(&paper);
    // Static: the files' 14 digits move the tip by about 1e-4 (calculix_beam.rs).
    within(
        "static tip under 1 N (m)",
        model.static_tip_deflection(1.0).unwrap(),
        reference.static_tip_deflection(1.0).unwrap(),
        2e-4,
    );
    let law = LawSource::resolve(&scene).unwrap();
    let run = run_scene(scene, &law, 1).unwrap();
    let built_in = summary_on(paper, reference);
    let ours = &run.summary;
    within(
        "breakaway (s)",
        ours.breakaway.unwrap(),
        built_in.breakaway.unwrap(),
        5e-3,
    );
    within(
        "period (s)",
        ours.period.unwrap(),
        built_in.period.unwrap(),
        5e-3,
    );
    let (lo, hi) = ours.corridor.unwrap();
    let (lo_ref, hi_ref) = built_in.corridor.unwrap();
    within("corridor min (m)", lo, lo_ref, 5e-3);
    within("corridor max (m)", hi, hi_ref, 5e-3);
    assert_eq!(ours.major_slips.len(), built_in.major_slips.len());
}

/// The example's section with `edit` applied to its TOML text, loaded from a scene file
/// next to the committed matrices (so that relative paths resolve as the example's).
fn edited(name: &str, edit: impl Fn(&str) -> String) -> Result<CheckedScene, String> {
    let text = std::fs::read_to_string(example().join("scene.toml")).unwrap();
    let dir = std::env::temp_dir().join(format!("structure-run-{}-{name}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    for ext in ["sti", "mas", "dof"] {
        let file = format!("beam.{ext}");
        std::fs::copy(example().join(&file), dir.join(&file)).unwrap();
    }
    let path = dir.join("scene.toml");
    std::fs::write(&path, edit(&text)).unwrap();
    let loaded = Scene::load(&path).map_err(|e| e.to_string());
    let built = loaded.and_then(|scene| {
        StructuralModel::build(&scene)
            .map(|_| scene)
            .map_err(|e| e.to_string())
    });
    std::fs::remove_dir_all(&dir).unwrap();
    built
}

fn refused(name: &str, edit: impl Fn(&str) -> String, needles: &[&str]) {
    let error = edited(name, edit).err().unwrap();
    println!("{name}: {error}");
    for needle in needles {
        assert!(error.contains(needle), "{name}: '{needle}' not in: {error}");
    }
}

#[test]
fn the_example_loads_from_a_copy_with_its_paths_relative_to_the_scene_file() {
    assert!(edited("copy", str::to_string).is_ok());
}

#[test]
fn a_missing_file_is_refused_naming_it() {
    refused(
        "missing",
        |t| t.replace("job = \"beam\"", "job = \"nothere\""),
        &["[structure]", "nothere.dof", "no such file"],
    );
}

#[test]
fn a_contact_dof_not_in_the_files_is_refused_naming_it() {
    refused(
        "unknown",
        |t| t.replace("node = 502", "node = 9999"),
        &[
            "structure.contact",
            "node 9999 direction 2",
            "1002 free DOFs",
        ],
    );
}

#[test]
fn a_contact_by_group_is_refused_outside_a_gmsh_mesh() {
    refused(
        "group",
        |t| t.replace("node = 502", "group = \"tip\""),
        &[
            "invalid scene: structure.contact = group 'tip' direction 2",
            "a node number with structure.format = calculix: only a Gmsh mesh has physical groups",
        ],
    );
}

#[test]
fn an_unknown_clamped_dof_is_refused_naming_it() {
    refused(
        "unknown-clamped",
        |t| format!("{t}clamped = [{{ node = 9999, direction = 1 }}]\n"),
        &["clamped DOF node 9999 direction 1", "not in the DOF map"],
    );
}

#[test]
fn a_clamped_contact_dof_is_refused() {
    // Clamped by the scene: refused by the scene's check.
    refused(
        "clamped-by-scene",
        |t| format!("{t}clamped = [{{ node = 502, direction = 2 }}]\n"),
        &[
            "structure.contact",
            "node 502 direction 2",
            "structure.clamped fixes it",
        ],
    );
    // Removed by the files (the deck's *BOUNDARY fixes node 2 in y): refused when read.
    refused(
        "clamped-by-files",
        |t| t.replace("node = 502", "node = 2"),
        &["structure.contact = node 2 direction 2", "not a free DOF"],
    );
}

#[test]
fn fields_that_do_not_fit_the_format_or_the_scene_are_refused() {
    refused(
        "no-job",
        |t| t.replace("job = \"beam\"", ""),
        &["structure.job", "given with structure.format = calculix"],
    );
    refused(
        "foreign",
        |t| format!("{t}stiffness = \"k.mtx\"\n"),
        &["structure.stiffness", "belongs to the other format"],
    );
    refused(
        "damping",
        |t| format!("{t}damping = \"c.mtx\"\n"),
        &["structure.damping", "Rayleigh"],
    );
    refused(
        "direction",
        |t| t.replace("direction = 2", "direction = 7"),
        &["structure.contact", "direction in 1..=6"],
    );
    // modal and auto are the structure's (structure_modal.rs, structure_auto.rs).
    refused(
        "beam",
        |t| format!("[fidelity]\nlevel = \"beam\"\n{t}"),
        &[
            "fidelity.level = beam",
            "with a [structure]: beam is the built-in",
        ],
    );
    refused(
        "holding",
        |t| format!("[contact]\nholding_force = \"euler-bernoulli\"\n{t}"),
        &["contact.holding_force", "3 EI delta / L^3"],
    );
}

/// The same beam written as Matrix Market files (the lower triangle of ccx's upper one,
/// `symmetric`) with a DOF map file, named by a `format = "matrix-market"` section
/// with paths relative to its scene file: the same values in the same order, so the
/// same model to the bit (the readers differ, the checked structure does not).
#[test]
fn the_beam_as_matrix_market_files_gives_the_same_model() {
    let dir = std::env::temp_dir().join(format!("structure-run-{}-mtx", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let labels = std::fs::read_to_string(example().join("beam.dof")).unwrap();
    let rows = labels.lines().count();
    for (from, to) in [("beam.sti", "k.mtx"), ("beam.mas", "m.mtx")] {
        let text = std::fs::read_to_string(example().join(from)).unwrap();
        let entries: Vec<String> = text
            .lines()
            .map(|line| {
                let f: Vec<&str> = line.split_whitespace().collect();
                format!("{} {} {}", f[1], f[0], f[2])
            })
            .collect();
        let header = format!(
            "%%MatrixMarket matrix coordinate real symmetric\n{rows} {rows} {}\n",
            entries.len()
        );
        std::fs::write(dir.join(to), header + &entries.join("\n") + "\n").unwrap();
    }
    let map: String = labels.lines().map(|l| l.replace('.', " ") + "\n").collect();
    std::fs::write(dir.join("k.dofs"), map).unwrap();
    let scene_path = dir.join("scene.toml");
    std::fs::write(
        &scene_path,
        "[structure]\nformat = \"matrix-market\"\nstiffness = \"k.mtx\"\nmass = \"m.mtx\"\ndofs = \"k.dofs\"\ncontact = { node = 502, direction = 2 }\n",
    )
    .unwrap();
    let scene = Scene::load(&scene_path).unwrap();
    let model = StructuralModel::build(&scene);
    std::fs::remove_dir_all(&dir).unwrap();
    let model = model.unwrap();
    assert!(model.label.contains("matrix-market k"), "{}", model.label);
    let calculix = StructuralModel::build(&calculix_scene()).unwrap();
    assert_eq!(model.tip, calculix.tip);
    assert_eq!(
        model.static_tip_deflection(1.0).unwrap(),
        calculix.static_tip_deflection(1.0).unwrap()
    );
}

/// A damping matrix from a file (`structure.damping`, Matrix Market) equal to the
/// Rayleigh matrix C = a M + b K gives the run of the scene's Rayleigh damping with the
/// same a and b, on both integrators (the full model: a modal reduction refuses a
/// damping file). The file's entries are a m_ij + b k_ij in f64, written in Rust's
/// shortest round-trip form, so C0 is that sum exactly; the two runs differ only in how
/// the integrator rounds: (s_m + a c) M + (s_k + b c) K against s_m M + s_k K + c C0 in
/// the effective matrix, and the same split in the step's right-hand side, a few ulps
/// per entry. The stick-slip run amplifies such round-off at its transitions: moving b
/// by 1e-13 of itself moves the tip by 1.0e-8 m (generalised-alpha) and 2.9e-10 m
/// (Moreau-Jean) of a range of 8.06e-3 m, and the file against Rayleigh measured
/// 2.1e-8 m and 1.5e-10 m. Asserted: the file's run within ten times that sensitivity
/// (measured in the test) and within 1e-5 of the range, while the damping itself moves
/// the tip by 1.4e-3 m (asserted above 1e-4 of the range: a C0 left out, or scaled
/// wrongly in the effective matrix or the right-hand side, fails both).
#[test]
fn a_damping_file_equal_to_rayleigh_gives_the_rayleigh_run() {
    let dir = std::env::temp_dir().join(format!("structure-run-{}-c", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let labels = std::fs::read_to_string(example().join("beam.dof")).unwrap();
    let rows = labels.lines().count();
    let (a, b) = (30.0, 2e-5);
    // ccx's .sti and .mas share one pattern in one order (calculix.rs's module doc).
    let read = |file: &str| -> Vec<(String, String, f64)> {
        std::fs::read_to_string(example().join(file))
            .unwrap()
            .lines()
            .map(|line| {
                let f: Vec<&str> = line.split_whitespace().collect();
                (f[1].to_string(), f[0].to_string(), f[2].parse().unwrap())
            })
            .collect()
    };
    let (k, m) = (read("beam.sti"), read("beam.mas"));
    let c: Vec<(String, String, f64)> = k
        .iter()
        .zip(&m)
        .map(|((i, j, kv), (i2, j2, mv))| {
            assert_eq!((i, j), (i2, j2));
            (i.clone(), j.clone(), a * mv + b * kv)
        })
        .collect();
    for (entries, to) in [(&k, "k.mtx"), (&m, "m.mtx"), (&c, "c.mtx")] {
        let body: String = entries
            .iter()
            .map(|(i, j, v)| format!("{i} {j} {v:e}\n"))
            .collect();
        let header = format!(
            "%%MatrixMarket matrix coordinate real symmetric\n{rows} {rows} {}\n",
            entries.len()
        );
        std::fs::write(dir.join(to), header + &body).unwrap();
    }
    let map: String = labels.lines().map(|l| l.replace('.', " ") + "\n").collect();
    std::fs::write(dir.join("k.dofs"), map).unwrap();
    let run = |scheme: &str, rayleigh: (f64, f64), file: bool| {
        let path = dir.join("scene.toml");
        std::fs::write(
            &path,
            format!(
                "[time]\nend = 0.5\n[integrator]\nscheme = \"{scheme}\"\n[damping]\nmass_proportional = {:e}\nstiffness_proportional = {:e}\n[structure]\nformat = \"matrix-market\"\nstiffness = \"k.mtx\"\nmass = \"m.mtx\"\ndofs = \"k.dofs\"\n{}contact = {{ node = 502, direction = 2 }}\n",
                rayleigh.0,
                rayleigh.1,
                if file { "damping = \"c.mtx\"\n" } else { "" }
            ),
        )
        .unwrap();
        let scene = Scene::load(&path).unwrap();
        let model = StructuralModel::build(&scene).unwrap();
        assert_eq!(model.damping.is_some(), file);
        let law = LawSource::resolve(&scene).unwrap().law().unwrap();
        let mut sim = Simulator::with_model(scene, model, law).unwrap();
        let tips: Vec<f64> = sim
            .run(1)
            .unwrap()
            .iter()
            .map(|s| s.tip_deflection)
            .collect();
        tips
    };
    for scheme in ["generalized-alpha", "moreau-jean"] {
        let rayleigh = run(scheme, (a, b), false);
        let from_file = run(scheme, (0.0, 0.0), true);
        let undamped = run(scheme, (0.0, 0.0), false);
        let nudged = run(scheme, (a, b * (1.0 + 1e-13)), false);
        let range = rayleigh.iter().cloned().fold(f64::MIN, f64::max)
            - rayleigh.iter().cloned().fold(f64::MAX, f64::min);
        let largest = |x: &[f64], y: &[f64]| {
            assert_eq!(x.len(), y.len());
            x.iter()
                .zip(y)
                .map(|(p, q)| (p - q).abs())
                .fold(0.0, f64::max)
        };
        let (file_vs_rayleigh, damping_effect) = (
            largest(&from_file, &rayleigh),
            largest(&undamped, &rayleigh),
        );
        let sensitivity = largest(&nudged, &rayleigh);
        println!("{scheme}: tip range {range:.3e} m, file vs Rayleigh {file_vs_rayleigh:.2e} m, b moved by 1e-13 {sensitivity:.2e} m, damped vs undamped {damping_effect:.2e} m");
        assert!(file_vs_rayleigh < 1e-5 * range, "{scheme}");
        assert!(file_vs_rayleigh < 10.0 * sensitivity, "{scheme}");
        assert!(damping_effect > 1e-4 * range, "{scheme}");
    }
    // A modal reduction refuses the file rather than drop it.
    let path = dir.join("scene.toml");
    let text = std::fs::read_to_string(&path).unwrap();
    // The last run's scene had no damping file: name it again.
    let text = text.replace("contact = ", "damping = \"c.mtx\"\ncontact = ");
    std::fs::write(&path, format!("[fidelity]\nlevel = \"modal\"\n{text}")).unwrap();
    let modal = StructuralModel::build(&Scene::load(&path).unwrap());
    std::fs::remove_dir_all(&dir).unwrap();
    let message = modal.unwrap_err().to_string();
    assert!(message.contains("structure.damping"), "{message}");
}
