//! Correspondence projection on a 100k-triangle synthetic target frame with 100k source vertices
//! and their normals (200k normal rays, both directions), the workload of the parity tests.
//!
//! - `project/build`: `Bvh::build` (SAH tree, leaf-ordered triangles, normals, pseudo-normals,
//!   mean edge length) for 100k and 300k triangles, on one thread and on two; `unsigned_*` the
//!   same with `Bvh::build_unsigned` (no normals).
//! - `project/rays`: `project` (one line query per point, both directions at once) on one thread
//!   and on two; `cast_ray_1_thread` casts the 200k rays one direction at a time, like a
//!   single-ray tracer; the GPU variants with and without the per-call transfers.
//! - `project/closest_point`: `closest_points` for the 100k source vertices.
//! - `project/bounded`: the nearest triangle of each source vertex within 0.75 mean edge
//!   lengths, the surface built for it and queried once, as the sub-grid match's bound checks
//!   do: `tree` (`Bvh::build_unsigned`, `closest_points`) against `cells` (`Cells::new`,
//!   `Cells::nearest`), on one thread and on two.
//! - `project_cpu_time/*`: the CPU variants again, timed by the CPU time of the whole process
//!   instead of the wall clock. On a machine shared with other jobs a thread is not always
//!   scheduled, which the wall clock counts and CPU time does not, so these give the rate per busy
//!   thread; wall-clock scaling from one thread to two is only meaningful on idle cores.
//!
//! Throughput counts rays (two per projected point) or queries. Pipelines and the BVH upload
//! happen before timing. Without a GPU adapter only the CPU is measured.

#[path = "../tests/project_support/metaballs.rs"]
mod metaballs;
#[path = "../tests/project_support/workload.rs"]
mod workload;

use std::hint::black_box;
use std::sync::OnceLock;
use std::time::Duration;

use criterion::measurement::{Measurement, ValueFormatter, WallTime};
use criterion::{
    BenchmarkGroup, BenchmarkId, Criterion, Throughput, criterion_group, criterion_main,
};
use glam::Vec3;
use surftrack::compute::{Backend, BackendChoice};
use surftrack::mesh::IndexedMesh;
use surftrack::project::{Bvh, Cells, GpuQueries, ProjectOptions, closest_points, project};

/// Threads of the multi-threaded variants: the two cores of the reference measurements.
const THREADS: usize = 2;

struct Frames {
    target: IndexedMesh,
    large: IndexedMesh,
    points: Vec<Vec3>,
    normals: Vec<Vec3>,
    bvh: Bvh,
}

fn frames() -> &'static Frames {
    static FRAMES: OnceLock<Frames> = OnceLock::new();
    FRAMES.get_or_init(|| {
        let (target, points, normals) = workload::workload();
        let bvh = Bvh::build(&target).expect("bvh");
        Frames {
            target,
            large: metaballs::metaballs(305, 0.0, 0.0),
            points,
            normals,
            bvh,
        }
    })
}

fn pool(threads: usize) -> rayon::ThreadPool {
    rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .expect("thread pool")
}

fn gpu() -> Option<Backend> {
    match Backend::select(BackendChoice::Gpu) {
        Ok(backend) => Some(backend),
        Err(error) => {
            eprintln!("GPU variants skipped: {error}");
            None
        }
    }
}

/// CPU time of the whole process (every thread, the GPU driver's included), read from the
/// per-thread counters in `/proc/self/task/*/schedstat` (nanoseconds).
struct ProcessCpuTime;

static WALL_TIME: WallTime = WallTime;

fn process_cpu_ns() -> u64 {
    std::fs::read_dir("/proc/self/task")
        .expect("/proc/self/task")
        .filter_map(|task| {
            let path = task.ok()?.path().join("schedstat");
            let stat = std::fs::read_to_string(path).ok()?;
            stat.split_whitespace().next()?.parse::<u64>().ok()
        })
        .sum()
}

impl Measurement for ProcessCpuTime {
    type Intermediate = u64;
    type Value = Duration;

    fn start(&self) -> u64 {
        process_cpu_ns()
    }

    fn end(&self, start: u64) -> Duration {
        Duration::from_nanos(process_cpu_ns().saturating_sub(start))
    }

    fn add(&self, a: &Duration, b: &Duration) -> Duration {
        *a + *b
    }

    fn zero(&self) -> Duration {
        Duration::ZERO
    }

    fn to_f64(&self, value: &Duration) -> f64 {
        value.as_nanos() as f64
    }

    fn formatter(&self) -> &dyn ValueFormatter {
        WALL_TIME.formatter()
    }
}

fn short<M: Measurement>(group: &mut BenchmarkGroup<'_, M>) {
    group.sample_size(10);
    group.warm_up_time(Duration::from_secs(1));
    group.measurement_time(Duration::from_secs(3));
}

/// Which group [`cpu_groups`] is about to finish, for the variants [`other_variants`] adds.
#[derive(Clone, Copy, PartialEq)]
enum Stage {
    Build,
    Rays,
    ClosestPoint,
}

/// The CPU variants of the three groups, under measurement `M`; `extra` adds further variants to
/// each group before it is finished.
fn cpu_groups<M: Measurement>(
    c: &mut Criterion<M>,
    prefix: &str,
    extra: &dyn Fn(Stage, &mut BenchmarkGroup<'_, M>),
) {
    let f = frames();
    let pools = [(1, pool(1)), (THREADS, pool(THREADS))];
    let name = |threads: usize| {
        if threads == 1 {
            "1_thread".to_owned()
        } else {
            format!("{threads}_threads")
        }
    };

    let mut group = c.benchmark_group(format!("{prefix}/build"));
    short(&mut group);
    for mesh in [&f.target, &f.large] {
        let n = mesh.triangles.len();
        group.throughput(Throughput::Elements(n as u64));
        for (threads, pool) in &pools {
            group.bench_with_input(BenchmarkId::new(name(*threads), n), mesh, |b, mesh| {
                b.iter(|| pool.install(|| Bvh::build(black_box(mesh)).expect("bvh")))
            });
            group.bench_with_input(
                BenchmarkId::new(format!("unsigned_{}", name(*threads)), n),
                mesh,
                |b, mesh| {
                    b.iter(|| pool.install(|| Bvh::build_unsigned(black_box(mesh)).expect("bvh")))
                },
            );
        }
    }
    extra(Stage::Build, &mut group);
    group.finish();

    let options = ProjectOptions::default();
    let rays = 2 * f.points.len();
    let mut group = c.benchmark_group(format!("{prefix}/rays"));
    short(&mut group);
    group.throughput(Throughput::Elements(rays as u64));
    for (threads, pool) in &pools {
        group.bench_function(
            BenchmarkId::new(format!("cpu_{}", name(*threads)), rays),
            |b| {
                b.iter(|| {
                    pool.install(|| {
                        project(
                            &Backend::Cpu,
                            &f.bvh,
                            black_box(&f.points),
                            &f.normals,
                            &options,
                        )
                    })
                })
            },
        );
    }
    extra(Stage::Rays, &mut group);
    group.finish();

    let n = f.points.len();
    let mut group = c.benchmark_group(format!("{prefix}/closest_point"));
    short(&mut group);
    group.throughput(Throughput::Elements(n as u64));
    for (threads, pool) in &pools {
        group.bench_function(
            BenchmarkId::new(format!("cpu_{}", name(*threads)), n),
            |b| {
                b.iter(|| {
                    pool.install(|| {
                        closest_points(&Backend::Cpu, &f.bvh, black_box(&f.points), f32::INFINITY)
                    })
                })
            },
        );
    }
    extra(Stage::ClosestPoint, &mut group);
    group.finish();

    let mut group = c.benchmark_group(format!("{prefix}/bounded"));
    short(&mut group);
    group.throughput(Throughput::Elements(n as u64));
    let reach = BOUND;
    for (threads, pool) in &pools {
        group.bench_function(
            BenchmarkId::new(format!("tree_{}", name(*threads)), n),
            |b| {
                b.iter(|| {
                    pool.install(|| {
                        let bvh = Bvh::build_unsigned(black_box(&f.target)).expect("bvh");
                        closest_points(&Backend::Cpu, &bvh, &f.points, reach).expect("query")
                    })
                })
            },
        );
        group.bench_function(
            BenchmarkId::new(format!("cells_{}", name(*threads)), n),
            |b| {
                b.iter(|| {
                    pool.install(|| {
                        let cells = Cells::new(black_box(&f.target)).expect("cells");
                        cells.nearest(&f.points, reach).expect("query")
                    })
                })
            },
        );
    }
    group.finish();
}

/// The bound of `project/bounded`, in mean edge lengths: the sub-grid match's default distance
/// bound (`track::MAX_DISTANCE`) with the tracked and input edges alike.
const BOUND: f32 = 0.75;

/// The single-ray and GPU variants of `stage`, by the wall clock.
fn other_variants(stage: Stage, group: &mut BenchmarkGroup<'_, WallTime>, gpu: Option<&Backend>) {
    let f = frames();
    let options = ProjectOptions::default();
    let context = gpu.and_then(Backend::gpu);
    match stage {
        Stage::Build => {}
        Stage::Rays => {
            let rays = 2 * f.points.len();
            let single = pool(1);
            group.bench_function(BenchmarkId::new("cast_ray_1_thread", rays), |b| {
                b.iter(|| {
                    single.install(|| {
                        let mut hits = 0usize;
                        for (&p, &n) in f.points.iter().zip(&f.normals) {
                            for d in [n, -n] {
                                let hit = f.bvh.cast_ray(black_box(p), d, f32::INFINITY);
                                hits += usize::from(hit.is_some());
                            }
                        }
                        hits
                    })
                })
            });
            if let (Some(backend), Some(context)) = (gpu, context) {
                let resident = f.bvh.upload(context).expect("upload");
                let job = GpuQueries::project(context, &f.bvh, &f.points, &f.normals, &options)
                    .expect("upload");
                job.dispatch(context, &resident).expect("dispatch");
                job.read(context).expect("read");
                project(backend, &f.bvh, &f.points, &f.normals, &options).expect("warm");
                group.bench_function(BenchmarkId::new("gpu_with_transfer", rays), |b| {
                    b.iter(|| project(backend, &f.bvh, black_box(&f.points), &f.normals, &options))
                });
                group.bench_function(BenchmarkId::new("gpu_kernel", rays), |b| {
                    b.iter(|| {
                        job.dispatch(context, &resident).expect("dispatch");
                        context.wait().expect("wait")
                    })
                });
            }
        }
        Stage::ClosestPoint => {
            let n = f.points.len();
            if let (Some(backend), Some(context)) = (gpu, context) {
                let resident = f.bvh.upload(context).expect("upload");
                let job = GpuQueries::closest_points(context, &f.bvh, &f.points, f32::INFINITY)
                    .expect("upload");
                job.dispatch(context, &resident).expect("dispatch");
                job.read(context).expect("read");
                closest_points(backend, &f.bvh, &f.points, f32::INFINITY).expect("warm");
                group.bench_function(BenchmarkId::new("gpu_with_transfer", n), |b| {
                    b.iter(|| closest_points(backend, &f.bvh, black_box(&f.points), f32::INFINITY))
                });
                group.bench_function(BenchmarkId::new("gpu_kernel", n), |b| {
                    b.iter(|| {
                        job.dispatch(context, &resident).expect("dispatch");
                        context.wait().expect("wait")
                    })
                });
            }
        }
    }
}

fn wall_clock(c: &mut Criterion) {
    let gpu = gpu();
    cpu_groups(c, "project", &|stage, group| {
        other_variants(stage, group, gpu.as_ref())
    });
}

fn cpu_time(c: &mut Criterion<ProcessCpuTime>) {
    cpu_groups(c, "project_cpu_time", &|_, _| {});
}

criterion_group!(wall, wall_clock);
criterion_group! {
    name = cpu;
    config = Criterion::default().with_measurement(ProcessCpuTime);
    targets = cpu_time
}
criterion_main!(wall, cpu);
