//! The synthetic generator's defaults against the data set the paper's authors published
//! (data/paper-authors/exponential_friction_model_samples_full.csv, Apache-2.0, from
//! TUHH-DYN/NeuralNetworkFrictionModel_FEA): 5000 draws of F_n ~ U[98, 102] N and
//! v_s ~ N(0, 0.1 m/s), the 6 draws with |v_s| <= 1e-4 m/s removed, and
//! F_f = sign(v_s) mu(|v_s|) F_n (1 + 0.02 N(0, 1)).
//!
//! Every tolerance is a multiple of the statistic's standard error for these sample
//! sizes (n about 5000): `Z` standard errors for a mean or a standard deviation (a
//! two-sided chance of 6e-5 each for a correct generator), and the two-sample
//! Kolmogorov-Smirnov distance at the 0.1 % level. Both sets are held to the
//! distribution, and ours to theirs.

use std::path::PathBuf;

use stickslip::neural::SyntheticSpec;
use stickslip_train::csv::{read_csv_file, ColumnSelection};
use stickslip_train::data::Synthetic;
use stickslip_train::train::DEFAULT_SEED;
use stickslip_train::Dataset;

/// Standard errors allowed for a mean or a standard deviation.
const Z: f64 = 4.0;
/// Draws behind each set.
const DRAWS: f64 = 5000.0;
/// The authors' distribution (data/paper-authors/README.md).
const F_N_RANGE: (f64, f64) = (98.0, 102.0);
const V_STD: f64 = 0.1;
const V_CUT: f64 = 1e-4;
const RELATIVE_NOISE: f64 = 0.02;

/// One set's samples: normal force (N), sliding velocity (m/s) and the relative
/// residual F_f / (sign(v) mu(|v|) F_n) - 1 against the paper's Eq. 6.
struct Columns {
    normal_force: Vec<f64>,
    velocity: Vec<f64>,
    residual: Vec<f64>,
}

impl Columns {
    /// Features in the order (velocity, normal force), as the generator writes them.
    fn of(data: &Dataset) -> Columns {
        let law = SyntheticSpec::default();
        let velocity: Vec<f64> = data.inputs.row(0).iter().copied().collect();
        let normal_force: Vec<f64> = data.inputs.row(1).iter().copied().collect();
        let residual = (0..data.len())
            .map(|i| data.targets[i] / law.exact_force(velocity[i], normal_force[i]) - 1.0)
            .collect();
        Columns {
            normal_force,
            velocity,
            residual,
        }
    }

    fn len(&self) -> f64 {
        self.velocity.len() as f64
    }
}

fn authors_full_file() -> Columns {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../data/paper-authors/exponential_friction_model_samples_full.csv");
    let selection = ColumnSelection {
        features: vec!["vs".into(), "Fn".into()],
        target: "Ff".into(),
        sliding_velocity: Some("vs".into()),
        normal_force: Some("Fn".into()),
    };
    Columns::of(&read_csv_file(&path, &selection).expect("the authors' full data set"))
}

fn mean_std(values: &[f64]) -> (f64, f64) {
    let n = values.len() as f64;
    let mean = values.iter().sum::<f64>() / n;
    let var = values.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / n;
    (mean, var.sqrt())
}

/// Two-sample Kolmogorov-Smirnov distance: the largest gap between the empirical CDFs.
fn ks_distance(a: &[f64], b: &[f64]) -> f64 {
    let sorted = |x: &[f64]| {
        let mut x = x.to_vec();
        x.sort_by(f64::total_cmp);
        x
    };
    let (a, b) = (sorted(a), sorted(b));
    let (mut i, mut j, mut d) = (0, 0, 0.0_f64);
    while i < a.len() && j < b.len() {
        let x = a[i].min(b[j]);
        while i < a.len() && a[i] <= x {
            i += 1;
        }
        while j < b.len() && b[j] <= x {
            j += 1;
        }
        d = d.max((i as f64 / a.len() as f64 - j as f64 / b.len() as f64).abs());
    }
    d
}

/// The KS distance two samples of one distribution stay below with probability 99.9 %:
/// c(alpha) sqrt((n + m) / (n m)), c = sqrt(-ln(alpha / 2) / 2).
fn ks_critical(n: f64, m: f64) -> f64 {
    (-stickslip::elementary::ln(0.001 / 2.0) / 2.0).sqrt() * ((n + m) / (n * m)).sqrt()
}

/// Checks one set against the distribution; returns what failed, empty when all holds.
fn departures(set: &Columns) -> Vec<String> {
    let mut failed = Vec::new();
    let smallest_speed = set
        .velocity
        .iter()
        .fold(f64::INFINITY, |m, v| m.min(v.abs()));
    if smallest_speed <= V_CUT {
        failed.push(format!("|v_s| = {smallest_speed} m/s was not removed"));
    }
    let n = set.len();
    let mut check = |what: &str, value: f64, expected: f64, tolerance: f64| {
        if (value - expected).abs() > tolerance {
            failed.push(format!(
                "{what} {value} (expected {expected} +- {tolerance})"
            ));
        }
    };
    // Removed draws ~ Binomial(5000, p), p = P(|v| <= cut) = 2 phi(0) cut / sigma to
    // 1e-7 relative (cut / sigma = 1e-3): 4.0 +- 2.0 of 5000.
    let p = 2.0 * V_CUT / V_STD / (2.0 * std::f64::consts::PI).sqrt();
    let removed_sd = (DRAWS * p * (1.0 - p)).sqrt();
    check("draws removed", DRAWS - n, DRAWS * p, Z * removed_sd);
    // F_n ~ U[a, b): width w, std w / sqrt(12); the standard error of the sample std is
    // sqrt((mu4 - sigma^4) / (4 sigma^2 n)) with mu4 = w^4 / 80.
    let (a, b) = F_N_RANGE;
    let w = b - a;
    let sigma_u = w / 12f64.sqrt();
    let (mean, std) = mean_std(&set.normal_force);
    check("F_n mean", mean, (a + b) / 2.0, Z * sigma_u / n.sqrt());
    let std_se = ((w.powi(4) / 80.0 - sigma_u.powi(4)) / (4.0 * sigma_u.powi(2) * n)).sqrt();
    check("F_n std", std, sigma_u, Z * std_se);
    // The extremes lie within w / n of the bounds on average (exponential gaps): 10 times
    // that is passed with probability 1 - e^-10.
    let (lo, hi) = set
        .normal_force
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), f| {
            (l.min(*f), h.max(*f))
        });
    check("F_n min", lo, a + 5.0 * w / n, 5.0 * w / n);
    check("F_n max", hi, b - 5.0 * w / n, 5.0 * w / n);
    // v_s ~ N(0, sigma) (the cut removes 0.08 % of the mass, all at 0: the std grows by
    // 0.04 %, a twentieth of its standard error sigma / sqrt(2 n)).
    let (mean, std) = mean_std(&set.velocity);
    check("v_s mean", mean, 0.0, Z * V_STD / n.sqrt());
    check("v_s std", std, V_STD, Z * V_STD / (2.0 * n).sqrt());
    // Relative residual ~ N(0, 0.02).
    let (mean, std) = mean_std(&set.residual);
    check("residual mean", mean, 0.0, Z * RELATIVE_NOISE / n.sqrt());
    check(
        "residual std",
        std,
        RELATIVE_NOISE,
        Z * RELATIVE_NOISE / (2.0 * n).sqrt(),
    );
    failed
}

/// The KS distances of F_n, v_s and the residual between two sets that fail.
fn distribution_gaps(ours: &Columns, theirs: &Columns) -> Vec<String> {
    let critical = ks_critical(ours.len(), theirs.len());
    [
        ("F_n", &ours.normal_force, &theirs.normal_force),
        ("v_s", &ours.velocity, &theirs.velocity),
        ("residual", &ours.residual, &theirs.residual),
    ]
    .into_iter()
    .map(|(what, a, b)| (what, ks_distance(a, b)))
    .filter(|(_, d)| *d >= critical)
    .map(|(what, d)| format!("{what}: KS distance {d:.4} >= {critical:.4}"))
    .collect()
}

#[test]
fn the_authors_file_has_the_distribution_their_readme_reads_off_it() {
    let theirs = authors_full_file();
    assert_eq!(theirs.len(), 4994.0);
    let failed = departures(&theirs);
    assert!(failed.is_empty(), "{failed:#?}");
}

#[test]
fn the_default_generator_draws_the_authors_distribution() {
    let ours = Columns::of(&SyntheticSpec::default().generate(DEFAULT_SEED).unwrap());
    let theirs = authors_full_file();
    let failed = departures(&ours);
    assert!(failed.is_empty(), "{failed:#?}");
    let gaps = distribution_gaps(&ours, &theirs);
    assert!(gaps.is_empty(), "{gaps:#?}");
    // The means of both sets differ by less than Z standard errors of a difference.
    for (what, a, b, sigma) in [
        (
            "F_n",
            &ours.normal_force,
            &theirs.normal_force,
            4.0 / 12f64.sqrt(),
        ),
        ("v_s", &ours.velocity, &theirs.velocity, V_STD),
        ("residual", &ours.residual, &theirs.residual, RELATIVE_NOISE),
    ] {
        let gap = mean_std(a).0 - mean_std(b).0;
        let se = sigma * (1.0 / ours.len() + 1.0 / theirs.len()).sqrt();
        assert!(gap.abs() < Z * se, "{what} means differ by {gap}");
    }
}

/// The comparison can fail: the generator as it was before the authors' data were read
/// (F_n in [90, 110] N, additive noise) is told apart on F_n and on the noise.
#[test]
fn the_former_generator_is_told_apart() {
    let former = Columns::of(&SyntheticSpec::former().generate(DEFAULT_SEED).unwrap());
    let failed = departures(&former);
    for what in ["F_n std", "F_n min", "residual std"] {
        assert!(failed.iter().any(|f| f.starts_with(what)), "{failed:#?}");
    }
    let gaps = distribution_gaps(&former, &authors_full_file());
    assert!(gaps.iter().any(|g| g.starts_with("F_n")), "{gaps:#?}");
    assert!(gaps.iter().any(|g| g.starts_with("residual")), "{gaps:#?}");
}
