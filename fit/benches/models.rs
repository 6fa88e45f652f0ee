//! Throughput of the fitted models in f64 (one core), read from the committed
//! coefficient files: the cost column of REPORT.md in evaluations per second.

use airlight_fit::coeffs::load_dir;
use airlight_fit::model::Model;
use airlight_truth::domains::{Domain, VALIDATION_SEED};
use criterion::{criterion_group, criterion_main, Criterion, Throughput};
use std::hint::black_box;
use std::path::Path;

fn bench(c: &mut Criterion) {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../generated/coefficients");
    let files = load_dir(&dir).expect("committed coefficient files");
    let mut group = c.benchmark_group("models");
    for f in &files {
        for domain in [Domain::Thin, Domain::Dense] {
            let pts = domain.validation_set(f.model.g_range, 1000, VALIDATION_SEED ^ 0xBE7C);
            group.throughput(Throughput::Elements(pts.len() as u64));
            group.bench_function(format!("{}/{}", f.model.name, domain.name()), |b| {
                b.iter(|| pts.iter().map(|&p| black_box(f.model.eval_unchecked(black_box(p)))).sum::<f64>())
            });
        }
    }
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
