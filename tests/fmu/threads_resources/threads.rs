//! Many instances in many threads, interleaved, give the outputs of one instance alone,
//! bit for bit; so does a run after fmi2Reset.

use super::*;

/// The friction laws the instances of one thread use, all on the paper scene.
const LAWS: [(FrictionLawKind, &str); 4] = [
    (FrictionLawKind::Exponential, "paper-plain.json"),
    (FrictionLawKind::Neural, "paper-plain.json"),
    (FrictionLawKind::Coulomb, "paper-plain.json"),
    (FrictionLawKind::Neural, "paper-signed.json"),
];

fn alone(config: Config) -> Vec<Point> {
    let mut run = Run::start(config, &repository_uri());
    run.run_to_end();
    run.finish()
}

const THREADS: usize = 8;
const PER_THREAD: usize = 4;

/// Instance `j` of thread `t`: the laws rotate, and two instances are at beam fidelity.
fn config_of(t: usize, j: usize) -> Config {
    let (law, weights) = LAWS[(t + j) % LAWS.len()];
    let fidelity = if (t, j) == (0, 0) || (t, j) == (5, 2) {
        FidelityLevel::Beam
    } else {
        FidelityLevel::Modal
    };
    Config {
        fidelity,
        law,
        weights,
    }
}

#[test]
fn thirty_two_instances_in_eight_threads_equal_one_instance_alone_bit_for_bit() {
    let start = std::time::Instant::now();
    let mut configs: Vec<Config> = (0..THREADS)
        .flat_map(|t| (0..PER_THREAD).map(move |j| config_of(t, j)))
        .collect();
    configs.sort_by_key(|c| (c.fidelity.code(), c.law.code(), c.weights));
    configs.dedup();
    let references: Vec<(Config, Vec<Point>)> = configs.iter().map(|&c| (c, alone(c))).collect();
    let reference = |config: Config| {
        &references
            .iter()
            .find(|(c, _)| *c == config)
            .expect("a reference for every configuration")
            .1
    };
    // Every configuration gives different outputs, so an instance that picked up
    // another's data would show.
    for (k, (a, ra)) in references.iter().enumerate() {
        for (b, rb) in &references[k + 1..] {
            assert!(first_difference(ra, rb).is_some(), "{a:?} and {b:?} agree");
        }
    }
    let alone_time = start.elapsed();

    let barrier = Barrier::new(THREADS);
    let uri = repository_uri();
    let results: Vec<Vec<Vec<Point>>> = std::thread::scope(|scope| {
        let handles: Vec<_> = (0..THREADS)
            .map(|t| {
                let (barrier, uri) = (&barrier, &uri);
                scope.spawn(move || {
                    let mut runs: Vec<Run> = (0..PER_THREAD)
                        .map(|j| Run::start(config_of(t, j), uri))
                        .collect();
                    barrier.wait();
                    // Interleaved: one communication step of each instance in turn.
                    for _ in 0..STEPS {
                        for run in &mut runs {
                            run.step();
                        }
                    }
                    runs.into_iter().map(Run::finish).collect::<Vec<_>>()
                })
            })
            .collect();
        handles.into_iter().map(|h| h.join().unwrap()).collect()
    });

    let mut checked = 0;
    for (t, runs) in results.iter().enumerate() {
        for (j, points) in runs.iter().enumerate() {
            let config = config_of(t, j);
            assert_eq!(
                first_difference(points, reference(config)),
                None,
                "thread {t}, instance {j} ({config:?}) differs from the instance alone"
            );
            checked += 1;
        }
    }
    let transitions: Vec<u64> = references.iter().map(|(_, r)| r[STEPS - 1][6]).collect();
    println!(
        "{checked} instances in {THREADS} threads, {STEPS} points each: bit-identical to {} \
         instances alone (stick/slip transitions at 1.2 s: {transitions:?}); alone {:.2} s, \
         total {:.2} s",
        references.len(),
        alone_time.as_secs_f64(),
        start.elapsed().as_secs_f64()
    );
}

#[test]
fn a_run_after_fmi2_reset_repeats_the_first_bit_for_bit() {
    for config in [
        config_of(0, 1),
        Config {
            fidelity: FidelityLevel::Beam,
            law: FrictionLawKind::Neural,
            weights: "paper-signed.json",
        },
    ] {
        let mut run = Run::start(config, &repository_uri());
        run.run_to_end();
        let first = run.reset(config);
        run.run_to_end();
        let second = run.finish();
        assert_eq!(first_difference(&first, &second), None, "{config:?}");
        assert!(first[STEPS - 1][6] > 0, "no stick/slip transition");
    }
}
