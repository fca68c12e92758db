//! `hydroid calibrate` on the bundled spheroid joint twin (configs/spheroid_joint.toml):
//! 100 replicas of its polar, PMM and manoeuvre runs made from the identified model and
//! identified again, in parallel (rayon, as many threads as cores). Issue 22's target: under
//! 30 s on 2 cores.
//!
//! `cargo bench --bench calibrate`; numbers are recorded in docs/performance.md.

use criterion::{criterion_group, criterion_main, Criterion};
use hydroid::app::calibrate::{calibrate, Settings, DEFAULT_SEED};
use hydroid::app::pipeline::{self, Scope};
use hydroid::base::progress::Silent;
use std::hint::black_box;
use std::path::PathBuf;

fn bench(c: &mut Criterion) {
    let config = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("configs/spheroid_joint.toml");
    let loaded = hydroid::config::load(&config, &[]).expect("the bundled configuration loads");
    let inputs = pipeline::load_inputs(&loaded, pipeline::stage_inputs(&loaded.config))
        .expect("the bundled exports read");
    let original = pipeline::run_on(&loaded, &inputs, &mut Silent, Scope::Full)
        .expect("the bundled twin is identified");
    let settings = Settings {
        replicas: 100,
        seed: DEFAULT_SEED,
    };
    let mut g = c.benchmark_group("calibrate");
    g.sample_size(10);
    g.bench_function("spheroid_joint_100_replicas", |b| {
        b.iter(|| {
            let cal = calibrate(&loaded, &inputs, &original, settings, &|_| {})
                .expect("the replicas are identified");
            black_box(cal.converged)
        })
    });
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
