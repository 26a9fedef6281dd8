//! Complete telemetry snapshots per second over the Modbus link, against the in-process fake
//! arm on loopback. Each iteration is one `read_telemetry`: four reads (discrete inputs 0-94,
//! input registers 0-13 and 34-139, holding registers 0-107) and the decode. Target: 1,000/s.

#[path = "../tests/modbus_fake/mod.rs"]
mod modbus_fake;

use std::time::Duration;

use armjog::link::{ModbusConfig, ModbusLink};
use criterion::{Criterion, Throughput, criterion_group, criterion_main};

fn full_snapshot_polls(c: &mut Criterion) {
    let runtime = tokio::runtime::Builder::new_multi_thread()
        .worker_threads(2)
        .enable_all()
        .build()
        .expect("runtime");
    let (arm, link) = runtime.block_on(async {
        let arm = modbus_fake::FakeArm::start().await;
        arm.with(|s| {
            modbus_fake::fill_known_telemetry(s);
            s.record = false;
        });
        let mut config = ModbusConfig::new(arm.addr());
        config.poll_rate_hz = None;
        let (link, _events) = ModbusLink::connect(config).await.expect("connect");
        (arm, link)
    });
    let mut group = c.benchmark_group("modbus");
    group.throughput(Throughput::Elements(1));
    group.measurement_time(Duration::from_secs(5));
    group.bench_function("full_snapshot_poll", |b| {
        b.iter(|| {
            runtime
                .block_on(link.read_telemetry())
                .expect("a complete snapshot")
        })
    });
    group.finish();
    drop(link);
    drop(arm);
}

criterion_group!(benches, full_snapshot_polls);
criterion_main!(benches);
