//! Throughput of the generated f32 Rust kernels (`airlight-kernels`, one core)
//! next to the f64 models they come from, on the same points: what f32 and the
//! code generator buy on the CPU, for airlight's models and the baselines
//! (`airlight bench` measures every model, errors beside cost, in one run).
//! `cargo bench -p airlight-tests --bench kernels`.

use airlight_fit::model::Model;
use airlight_truth::domains::{Domain, VALIDATION_SEED};
use criterion::{criterion_group, criterion_main, Criterion, Throughput};
use std::hint::black_box;

fn bench(c: &mut Criterion) {
    let models = airlight_tests::committed_models();
    let mut group = c.benchmark_group("kernels");
    // Every shipped model: airlight's and the baselines.
    let names: Vec<String> = models.iter().map(|m| m.model.name.clone()).collect();
    for name in names.iter().map(String::as_str) {
        let m = models.iter().find(|m| m.model.name == name).expect("committed model");
        let k = airlight_kernels::kernel(name).expect("generated kernel");
        for domain in [Domain::Thin, Domain::Dense] {
            let pts = domain.validation_set(m.model.g_range, 1000, VALIDATION_SEED ^ 0xBE7C);
            let args: Vec<[f32; 4]> = pts
                .iter()
                .map(|p| {
                    [p.tau as f32, p.gamma as f32, if p.rho.is_infinite() { -1.0 } else { p.rho as f32 }, p.g as f32]
                })
                .collect();
            group.throughput(Throughput::Elements(pts.len() as u64));
            group.bench_function(format!("{name}/{}/f64-model", domain.name()), |b| {
                b.iter(|| pts.iter().map(|&p| black_box(m.model.eval_unchecked(black_box(p)))).sum::<f64>())
            });
            group.bench_function(format!("{name}/{}/f32-kernel", domain.name()), |b| {
                b.iter(|| args.iter().map(|a| black_box((k.airlight)(a[0], a[1], a[2], a[3]))).sum::<f32>())
            });
        }
    }
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
