//! The generated kernels' own f32 elementary functions (`airlight_kernels::math`,
//! `no_std`) against the platform's (`std`, which calls the C library or LLVM's
//! intrinsics), on the ranges the kernels use them on: what a kernel pays for
//! carrying its own. `cargo bench -p airlight-tests --bench math`.

use airlight_kernels::math;
use criterion::{criterion_group, criterion_main, Criterion, Throughput};
use std::hint::black_box;

fn grid(n: usize, lo: f32, hi: f32) -> Vec<f32> {
    (0..n).map(|i| lo + (hi - lo) * (i as f32 + 0.5) / n as f32).collect()
}

fn bench(c: &mut Criterion) {
    let n = 4096;
    let mut group = c.benchmark_group("math");
    group.throughput(Throughput::Elements(n as u64));
    type F = fn(f32) -> f32;
    let cases: [(&str, Vec<f32>, F, F); 6] = [
        ("exp", grid(n, -80.0, 0.0), math::exp, f32::exp),
        ("ln", grid(n, 1e-6, 1e3), math::ln, f32::ln),
        ("sqrt", grid(n, 1e-6, 1e6), math::sqrt, f32::sqrt),
        ("atan", grid(n, -50.0, 50.0), math::atan, f32::atan),
        ("sin", grid(n, 0.0, 3.2), |x| math::sin_cos(x).0, f32::sin),
        ("cos", grid(n, 0.0, 3.2), |x| math::sin_cos(x).1, f32::cos),
    ];
    // Independent evaluations into a buffer (no reduction chain to hide their
    // latency behind), the inputs and the outputs black-boxed.
    let mut out = vec![0.0f32; n];
    for (name, xs, ours, platform) in cases {
        for (who, f) in [("airlight", ours), ("std", platform)] {
            group.bench_function(format!("{name}/{who}"), |b| {
                b.iter(|| {
                    for (o, &x) in out.iter_mut().zip(black_box(&xs)) {
                        *o = f(x);
                    }
                    black_box(&mut out);
                })
            });
        }
    }
    // The kernels need both: one sin_cos against std's sin and cos.
    for (who, f) in [
        ("airlight", (|x: f32| math::sin_cos(x)) as fn(f32) -> (f32, f32)),
        ("std", (|x: f32| (x.sin(), x.cos())) as fn(f32) -> (f32, f32)),
    ] {
        let xs = grid(n, 0.0, 3.2);
        let mut out2 = vec![(0.0f32, 0.0f32); n];
        group.bench_function(format!("sin_cos/{who}"), |b| {
            b.iter(|| {
                for (o, &x) in out2.iter_mut().zip(black_box(&xs)) {
                    *o = f(x);
                }
                black_box(&mut out2);
            })
        });
    }
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
