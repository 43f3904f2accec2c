//! The SSP system files and fmucontainer link lists fmu-build writes
//! (`target/fmu/2.0/<system>.ssp`, `.csv`): what they hold, that it comes from the FMUs'
//! tables, and that they are reproducible. The masters that run them are driven by
//! `python-checks/tests/test_masters.py`.

use fmu_build::ssp::{
    self, CheckedSystem, Component, Connection, Setting, SspError, System, Value, PARAMETER_SET,
};
use std::collections::BTreeMap;
use std::io::Read;
use stickslip::choice::Choice;
use stickslip::friction::FrictionLawKind;
use stickslip::simulation::ExternalCoupling;
use stickslip_fmi::friction::NeuralFrictionLaw;
use stickslip_fmi::FmuKind;

fn checked(system: System) -> CheckedSystem {
    system
        .check()
        .unwrap_or_else(|e| panic!("{}: {e}", system.name))
}

/// The entries of a zip archive: name -> bytes, and the names in archive order.
fn entries(path: &std::path::Path) -> (Vec<String>, BTreeMap<String, Vec<u8>>) {
    let file = std::fs::File::open(path).unwrap_or_else(|e| {
        panic!(
            "{}: {e}; run `cargo run --release -p fmu-build` first",
            path.display()
        )
    });
    let mut archive = zip::ZipArchive::new(file).unwrap();
    let mut names = Vec::new();
    let mut map = BTreeMap::new();
    for k in 0..archive.len() {
        let mut entry = archive.by_index(k).unwrap();
        let mut bytes = Vec::new();
        entry.read_to_end(&mut bytes).unwrap();
        let name = entry.name().unwrap().into_owned();
        names.push(name.clone());
        map.insert(name, bytes);
    }
    (names, map)
}

/// The `name="value"` attributes of every `<ScalarVariable ... causality="parameter">`
/// of a model description with the text of its start value.
fn parameter_starts(xml: &str) -> Vec<(String, String)> {
    xml.split("<ScalarVariable ")
        .skip(1)
        .filter(|block| block.contains(r#"causality="parameter""#))
        .map(|block| {
            let value = |tag: &str, name: &str| {
                let start = tag.find(&format!(" {name}=\"")).unwrap() + name.len() + 3;
                tag[start..start + tag[start..].find('"').unwrap()].to_string()
            };
            let head = format!(" {}", &block[..block.find('>').unwrap()]);
            let body = &block[block.find('>').unwrap()..];
            let element = &body[..body.find("/>").unwrap()];
            (value(&head, "name"), value(element, "start"))
        })
        .collect()
}

/// The (name, value text) of every `<ssv:Parameter>` of component `component` in `ssd`.
fn ssd_parameters(ssd: &str, component: &str) -> Vec<(String, String)> {
    let start = ssd
        .find(&format!(r#"<ssd:Component name="{component}""#))
        .unwrap();
    let block = &ssd[start..start + ssd[start..].find("</ssd:Component>").unwrap()];
    block
        .split("<ssv:Parameter name=\"")
        .skip(1)
        .map(|p| {
            let name = &p[..p.find('"').unwrap()];
            let v = p.find(" value=\"").unwrap() + 8;
            (
                name.to_string(),
                p[v..v + p[v..].find('"').unwrap()].to_string(),
            )
        })
        .collect()
}

#[test]
fn the_written_files_are_what_the_tables_generate_and_reproducible() {
    let fmu_dir = fmu_build::fmu_dir();
    let scratch = std::env::temp_dir().join(format!("stickslip-ssp-{}", std::process::id()));
    for system in ssp::systems() {
        let system = checked(system);
        let shipped = fmu_dir.join(format!("{}.ssp", system.name));
        let again = ssp::write_ssp(&system, &fmu_dir, &scratch).unwrap();
        assert_eq!(
            std::fs::read(&shipped).unwrap(),
            std::fs::read(&again).unwrap(),
            "{} is not what fmu-build writes now, or not reproducible",
            shipped.display()
        );
        let csv = std::fs::read_to_string(fmu_dir.join(format!("{}.csv", system.name))).unwrap();
        assert_eq!(csv, system.container_csv(), "{}.csv", system.name);
    }
    let _ = std::fs::remove_dir_all(scratch);
}

#[test]
fn each_archive_holds_the_description_and_the_packaged_fmus() {
    for system in ssp::systems() {
        let system = checked(system);
        let (names, files) = entries(&fmu_build::fmu_dir().join(format!("{}.ssp", system.name)));
        let mut expected = vec!["SystemStructure.ssd".to_string()];
        for c in &system.components {
            let name = format!("resources/{}.fmu", c.fmu.model_identifier());
            if !expected.contains(&name) {
                expected.push(name);
            }
        }
        assert_eq!(names, expected, "{}", system.name);
        assert_eq!(
            String::from_utf8(files["SystemStructure.ssd"].clone()).unwrap(),
            system.ssd()
        );
        for c in &system.components {
            let packaged = std::fs::read(fmu_build::fmu_path(c.fmu)).unwrap();
            assert!(
                files[&format!("resources/{}.fmu", c.fmu.model_identifier())] == packaged,
                "{}: {} differs from the packaged FMU",
                system.name,
                c.fmu.model_identifier()
            );
        }
    }
}

/// Every parameter of each FMU is in the SSD: at the model description's start value,
/// except the ones the system sets, which carry their codes.
#[test]
fn parameters_are_the_defaults_except_what_the_system_sets() {
    let coupled = checked(ssp::coupled()).ssd();
    let monolithic = checked(ssp::monolithic()).ssd();
    let beam_starts = parameter_starts(&FmuKind::StickSlipBeam.model_description());
    let friction_starts = parameter_starts(&FmuKind::NeuralFriction.model_description());
    let with = |starts: &[(String, String)], name: &str, value: i32| {
        starts
            .iter()
            .map(|(n, v)| {
                if n == name {
                    (n.clone(), value.to_string())
                } else {
                    (n.clone(), v.clone())
                }
            })
            .collect::<Vec<_>>()
    };
    // NeuralFriction: law, three coefficients, weights, state_velocity, and every law's
    // parameters (the registry's: LuGre's 3, rate-and-state's 6, Stribeck's 2, ...).
    let law_parameters = stickslip::friction::registry::parameters().count();
    assert!(beam_starts.len() > 20 && friction_starts.len() == 6 + law_parameters);
    assert_eq!(
        ssd_parameters(&coupled, "beam"),
        with(
            &with(
                &beam_starts,
                "friction.law",
                FrictionLawKind::External.code()
            ),
            "external.coupling",
            ExternalCoupling::Signed.code()
        )
    );
    assert_eq!(ssd_parameters(&coupled, "friction"), friction_starts);
    assert_eq!(
        ssd_parameters(&monolithic, "beam"),
        with(&beam_starts, "friction.law", FrictionLawKind::Neural.code())
    );
    // The friction FMU's default law is the network: the coupled system runs the same
    // plain network as the monolithic one embeds.
    assert!(friction_starts.contains(&("law".into(), NeuralFrictionLaw::NEURAL.code().to_string())));
    // The systems with a law with state differ from the coupled one in NeuralFriction's
    // law and the beam's coupling (table, issue 36): the same links and the table's 22,
    // the law's code in the parameter set.
    for (system, law) in [
        (
            ssp::coupled_rate_and_state(),
            NeuralFrictionLaw::RATE_AND_STATE,
        ),
        (ssp::coupled_lugre(), NeuralFrictionLaw::LUGRE),
    ] {
        let system = checked(system);
        let ssd = system.ssd();
        assert_eq!(
            ssd_parameters(&ssd, "beam"),
            with(
                &ssd_parameters(&coupled, "beam"),
                "external.coupling",
                ExternalCoupling::Table.code()
            )
        );
        assert_eq!(
            ssd_parameters(&ssd, "friction"),
            with(&friction_starts, "law", law.code()),
            "{}",
            system.name
        );
        let connections = checked(ssp::coupled()).connections;
        assert_eq!(system.connections[..connections.len()], connections[..]);
        let table = &system.connections[connections.len()..];
        assert_eq!(table.len(), 22);
        for (k, c) in table.iter().enumerate() {
            let (i, step) = (k / 2, k % 2 == 1);
            let (from, to) = if step {
                ("table_step_friction_force", "external.table_step_force")
            } else {
                ("table_friction_force", "external.table_force")
            };
            assert_eq!(c.from, ("friction", &*format!("{from}_{i}")));
            assert_eq!(c.to, ("beam", &*format!("{to}_{i}")));
        }
    }
    for ssd in [&coupled, &monolithic] {
        assert_eq!(
            ssd.matches(&format!(
                r#"<ssv:ParameterSet version="1.0" name="{PARAMETER_SET}">"#
            ))
            .count(),
            ssd.matches("<ssd:Component ").count()
        );
        assert!(!ssd.contains("Enumeration"));
        assert!(ssd.contains(r#"<osp:FixedStepAlgorithm baseStepSize="0.001"/>"#));
    }
}

/// The coupled system's links, as the SSD and the CSV write them: the beam's sliding
/// velocity into the friction law, whose force magnitude and static limit come back as
/// the beam's external inputs; every connected end is declared as a connector.
#[test]
fn the_coupled_system_is_wired_beam_to_friction_and_back() {
    let system = checked(ssp::coupled());
    let ssd = system.ssd();
    let csv = system.container_csv();
    let links = [
        ("beam", "relative_velocity", "friction", "sliding_velocity"),
        (
            "friction",
            "friction_force_magnitude",
            "beam",
            "external.kinetic_force",
        ),
        ("friction", "static_limit", "beam", "external.static_limit"),
        (
            "friction",
            "friction_force",
            "beam",
            "external.friction_force",
        ),
        (
            "friction",
            "friction_force_slope",
            "beam",
            "external.friction_slope",
        ),
        (
            "friction",
            "evaluated_velocity",
            "beam",
            "external.sliding_velocity",
        ),
        (
            "friction",
            "step_friction_force",
            "beam",
            "external.step_force",
        ),
        (
            "friction",
            "step_friction_slope",
            "beam",
            "external.step_slope",
        ),
        (
            "beam",
            "mean_relative_velocity",
            "friction",
            "mean_sliding_velocity",
        ),
    ];
    assert_eq!(ssd.matches("<ssd:Connection ").count(), links.len());
    for (a, x, b, y) in links {
        assert!(ssd.contains(&format!(
            r#"<ssd:Connection startElement="{a}" startConnector="{x}" endElement="{b}" endConnector="{y}"/>"#
        )));
        let file = |c: &str| {
            if c == "beam" {
                "StickSlipBeam.fmu"
            } else {
                "NeuralFriction.fmu"
            }
        };
        assert!(
            csv.contains(&format!("LINK;{};{x};{};{y}\n", file(a), file(b))),
            "{csv}"
        );
        for (component, connector, kind) in [(a, x, "output"), (b, y, "input")] {
            let c = system
                .components
                .iter()
                .find(|c| c.name == component)
                .unwrap();
            assert!(
                c.connectors
                    .iter()
                    .any(|p| p.name == connector && p.causality.as_str() == kind),
                "{component}.{connector}"
            );
        }
    }
    // The inputs nothing feeds are no connectors (fmpy would drive them with 0) but
    // container inputs.
    for (component, input) in [
        ("beam", "belt_speed"),
        ("beam", "normal_force"),
        ("friction", "normal_force"),
        ("friction", "extra_feature[1]"),
    ] {
        assert!(!ssd.contains(&format!(r#"<ssd:Connector name="{input}""#)));
        assert!(csv.contains(&format!(";{component}.{input};")), "{csv}");
    }
    // Beam first: the stepping order of a sequential container.
    assert!(
        csv.find("FMU;StickSlipBeam.fmu").unwrap() < csv.find("FMU;NeuralFriction.fmu").unwrap()
    );
    // Every parameter value is a START rule.
    let starts = csv.lines().filter(|l| l.starts_with("START;")).count();
    let parameters: usize = system.components.iter().map(|c| c.parameters.len()).sum();
    assert_eq!(starts, parameters);
    assert!(csv.contains(&format!(
        "START;StickSlipBeam.fmu;friction.law;{};\n",
        FrictionLawKind::External.code()
    )));
}

/// A Real parameter's text reads back to the default bit for bit.
#[test]
fn real_values_read_back_exactly() {
    let system = checked(ssp::monolithic());
    let mut reals = 0;
    for (name, value) in &system.components[0].parameters {
        if let Value::Real(x, _) = value {
            let ssd = system.ssd();
            let text = ssd_parameters(&ssd, "beam")
                .into_iter()
                .find(|(n, _)| n == name)
                .unwrap()
                .1;
            assert_eq!(
                text.parse::<f64>().unwrap().to_bits(),
                x.to_bits(),
                "{name}"
            );
            reals += 1;
        }
    }
    assert!(reals > 10);
}

/// A system that does not fit the tables is refused with the reason.
#[test]
fn systems_that_do_not_fit_the_tables_are_refused() {
    let base = ssp::coupled;
    let with_links = |connections: Vec<Connection>| System {
        connections,
        ..base()
    };
    let link = |from: (&'static str, &'static str), to: (&'static str, &'static str)| Connection {
        from,
        to,
    };
    let cases: Vec<(System, &str)> = vec![
        (
            with_links(vec![link(("beam", "tip_deflection"), ("friction", "sliding_velocit"))]),
            "NeuralFriction has no variable sliding_velocit",
        ),
        (
            with_links(vec![link(("friction", "sliding_velocity"), ("beam", "belt_speed"))]),
            "friction.sliding_velocity has causality input, not output",
        ),
        (
            with_links(vec![link(("beam", "tip_deflection"), ("friction", "law"))]),
            "friction.law has causality parameter, not input",
        ),
        (
            with_links(vec![link(("beam", "transitions"), ("friction", "normal_force"))]),
            "different types",
        ),
        (
            with_links(vec![
                link(("beam", "tip_velocity"), ("friction", "sliding_velocity")),
                link(("beam", "relative_velocity"), ("friction", "sliding_velocity")),
            ]),
            "friction.sliding_velocity is fed twice",
        ),
        (
            with_links(vec![link(("belt", "speed"), ("beam", "belt_speed"))]),
            "no component named belt",
        ),
        (
            System {
                components: vec![Component {
                    name: "beam",
                    fmu: FmuKind::StickSlipBeam,
                    set: vec![("friction.law", Setting::Choice("dahl"))],
                }],
                connections: vec![],
                ..base()
            },
            "not a FrictionModel word; allowed: 1 = exponential, 2 = coulomb, 3 = neural, 4 = external",
        ),
        (
            System {
                components: vec![Component {
                    name: "beam",
                    fmu: FmuKind::StickSlipBeam,
                    set: vec![("fidelity.modes", Setting::Integer(201))],
                }],
                connections: vec![],
                ..base()
            },
            "201 is outside [1, 200]",
        ),
        (
            System {
                components: vec![Component {
                    name: "beam",
                    fmu: FmuKind::StickSlipBeam,
                    set: vec![("geometry.length", Setting::Integer(2))],
                }],
                connections: vec![],
                ..base()
            },
            "the setting's type is not the variable's",
        ),
        (
            System {
                components: vec![Component {
                    name: "beam",
                    fmu: FmuKind::StickSlipBeam,
                    set: vec![("tip_deflection", Setting::Real(0.0))],
                }],
                connections: vec![],
                ..base()
            },
            "an output is not a parameter",
        ),
        (
            System {
                components: vec![
                    Component {
                        name: "beam",
                        fmu: FmuKind::StickSlipBeam,
                        set: vec![],
                    },
                    Component {
                        name: "beam",
                        fmu: FmuKind::NeuralFriction,
                        set: vec![],
                    },
                ],
                connections: vec![],
                ..base()
            },
            "component beam appears twice",
        ),
    ];
    for (system, expected) in cases {
        let error: SspError = system.check().unwrap_err();
        let message = error.to_string();
        assert!(
            message.contains(expected),
            "{message}\n  expected: {expected}"
        );
    }
}
