//! `hydroid plan` on the bundled spheroid (configs/spheroid.toml: polar, surge run and one
//! manoeuvre): 50 candidates ranked for every identified coefficient, the model's default set
//! at the manoeuvre's speed and at 2 m/s (42 captive runs and 8 free-running manoeuvres, each
//! through the hybrid EKF's covariance recursion), evaluated in parallel (rayon). Issue 26's
//! target: under 2 s on 2 cores.
//!
//! `cargo bench --bench planner`; numbers are recorded in docs/performance.md.

use criterion::{criterion_group, criterion_main, Criterion};
use hydroid::app::pipeline::{self, Scope};
use hydroid::app::plan::{self, candidate, Settings};
use hydroid::base::progress::Silent;
use std::hint::black_box;
use std::path::PathBuf;

fn bench(c: &mut Criterion) {
    let config = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("configs/spheroid.toml");
    let loaded = hydroid::config::load(&config, &[]).expect("the bundled configuration loads");
    let inputs = pipeline::load_inputs(&loaded, pipeline::stage_inputs(&loaded.config))
        .expect("the bundled exports read");
    let output = pipeline::run_on(&loaded, &inputs, &mut Silent, Scope::Full)
        .expect("the bundled example is identified");
    let mut candidates = Vec::new();
    for speed in [3.0, 2.0] {
        let abilities = candidate::Abilities {
            captive: true,
            rudder: false,
            planes: false,
            speed,
            length: 1.2,
        };
        for mut cand in candidate::defaults(abilities) {
            cand.name = format!("{} at {speed} m/s", cand.name);
            cand.speed = Some(speed);
            candidates.push(cand);
        }
    }
    assert_eq!(candidates.len(), 50);
    let settings = Settings {
        candidates,
        ..Settings::default()
    };
    let mut g = c.benchmark_group("plan");
    g.sample_size(10);
    g.bench_function("spheroid_50_candidates", |b| {
        b.iter(|| {
            let p = plan::plan(&loaded, &output, &settings).expect("the candidates rank");
            assert_eq!(p.ranked.len(), 50, "{:?}", p.skipped);
            black_box(p.ranked[0].d_score)
        })
    });
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
