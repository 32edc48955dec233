//! asperity-ca: the workloads. Evolution alone on an 8192² cyclic grid,
//! bit-sliced versus one byte per cell (the straightforward implementation), and
//! the full evolution + accumulation of 8192² × 256 steps.

use asperity_ca::evolve::{BitGrid, step_bytes};
use asperity_ca::{CaParams, Family, Init, Rule, accumulate, initial_grid};
use asperity_core::MemoryBudget;
use criterion::{BenchmarkId, Criterion, Throughput, criterion_group, criterion_main};

fn evolve(c: &mut Criterion) {
    let n = 8192;
    let rule = Rule::new(Family::Totalistic9, 2, 450).expect("valid rule");
    let init = initial_grid(
        &Init::Random {
            density: 0.3,
            seed: 7,
        },
        Some([n, n]),
        2,
        &MemoryBudget::unlimited(),
    )
    .expect("grid");
    let mut g = c.benchmark_group("ca/evolve_8192_rule450");
    g.sample_size(10);
    g.throughput(Throughput::Elements((n * n) as u64));
    let a = BitGrid::from_bytes(init.data(), n, n);
    let mut b = a.clone();
    g.bench_function(BenchmarkId::new("bit_sliced", "1 step"), |bench| {
        bench.iter(|| a.step_into(&rule, &mut b))
    });
    let src = init.data().to_vec();
    let mut dst = src.clone();
    g.bench_function(BenchmarkId::new("byte_per_cell", "1 step"), |bench| {
        bench.iter(|| step_bytes(&rule, &src, &mut dst, n, n))
    });
    g.finish();
}

fn full(c: &mut Criterion) {
    let (n, steps) = (8192, 256);
    let rule = Rule::new(Family::Totalistic9, 2, 450).expect("valid rule");
    let init = initial_grid(
        &Init::Random {
            density: 0.3,
            seed: 7,
        },
        Some([n, n]),
        2,
        &MemoryBudget::unlimited(),
    )
    .expect("grid");
    let mut g = c.benchmark_group("ca/accumulate_8192x256_rule450");
    g.sample_size(10);
    g.throughput(Throughput::Elements((n * n * steps) as u64));
    let p = CaParams::new(rule, steps);
    g.bench_function("bit_sliced_counters", |bench| {
        bench.iter(|| accumulate(&init, &p, &MemoryBudget::unlimited()).expect("run"))
    });
    g.finish();
}

criterion_group!(benches, evolve, full);
criterion_main!(benches);
