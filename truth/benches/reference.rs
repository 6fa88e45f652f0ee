//! Throughput of the reference airlight (target: ≥ 50,000 isotropic evaluations
//! per second on one core).

use airlight_truth::domains::{Domain, VALIDATION_SEED};
use airlight_truth::reference::{airlight, airlight_e1, airlight_s_form};
use criterion::{criterion_group, criterion_main, BatchSize, Criterion, Throughput};
use std::hint::black_box;

fn bench(c: &mut Criterion) {
    let mut group = c.benchmark_group("reference");
    for (label, domain, g) in [
        ("isotropic/thin", Domain::Thin, (0.0, 0.0)),
        ("isotropic/dense", Domain::Dense, (0.0, 0.0)),
        ("hg/thin", Domain::Thin, (-0.9, 0.95)),
        ("hg/dense", Domain::Dense, (-0.9, 0.95)),
    ] {
        let pts = domain.validation_set(g, 1000, VALIDATION_SEED ^ 0xBE7C);
        group.throughput(Throughput::Elements(pts.len() as u64));
        group.bench_function(label, |b| {
            b.iter_batched(
                || pts.clone(),
                |pts| pts.into_iter().map(|p| black_box(airlight(p).unwrap())).sum::<f64>(),
                BatchSize::LargeInput,
            )
        });
    }
    let pts = Domain::Thin.validation_set((0.0, 0.0), 200, VALIDATION_SEED ^ 0xBE7C);
    group.throughput(Throughput::Elements(pts.len() as u64));
    group.bench_function("cross-check/e1", |b| {
        b.iter(|| pts.iter().map(|&p| black_box(airlight_e1(p).unwrap().0)).sum::<f64>())
    });
    group.bench_function("cross-check/s-form", |b| {
        b.iter(|| pts.iter().map(|&p| black_box(airlight_s_form(p).unwrap())).sum::<f64>())
    });
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
