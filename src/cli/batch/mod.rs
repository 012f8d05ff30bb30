//! `surftrack batch MANIFEST -o OUTROOT`: every cache of a manifest tracked into its own folder
//! (`OUTROOT/NAME/`, the layout of `track`), several at once, each resumable, with optional
//! follow-up steps; or, on a farm, one cache per task (`--index`, or the engine's array index).

mod cache;
mod jobs;
mod progress;

use super::CliError;
use super::propagate::PropagateArgs;
use super::track::MethodParams;
use cache::{CacheRun, Outcome, Request};
use clap::Args;
use progress::BatchProgress;
use std::path::PathBuf;
use std::sync::atomic::{AtomicUsize, Ordering};
use surftrack::batch::{BatchReport, Cache, Manifest, STATUS_FILE, table, task_index};
use surftrack::compute::{Backend, BackendChoice};

#[derive(Debug, Args)]
pub struct BatchArgs {
    /// One cache per line: a folder or a frame pattern, as `track` takes (relative paths from the
    /// manifest's folder); blank lines and `#` comments are ignored.
    pub manifest: PathBuf,
    /// Output root: each cache goes into OUTROOT/NAME/ (NAME from the cache's folder, made
    /// unique), the assembled report into OUTROOT/batch.json.
    #[arg(short, long)]
    pub out: PathBuf,
    /// Caches tracked at once. Default: from the cores (two each: tracking, and the read-ahead and
    /// field sampling beside it) and the memory the largest first frame needs.
    #[arg(long, short)]
    pub jobs: Option<usize>,
    /// Run only the cache at this index of the manifest (0-based, blank lines and comments not
    /// counted). Without it, SLURM_ARRAY_TASK_ID or JOB_COMPLETION_INDEX choose, when set. One
    /// cache writes only its own folder; `--report` assembles batch.json afterwards.
    #[arg(long)]
    pub index: Option<usize>,
    /// Run nothing: assemble OUTROOT/batch.json and the table from the caches' status files (the
    /// last step of a farm job). Exits non-zero unless every cache is done.
    #[arg(long, conflicts_with = "index")]
    pub report: bool,
    /// Where the data-parallel stages run: auto, cpu or gpu.
    #[arg(long, value_enum, default_value_t = BackendChoice::Auto)]
    pub backend: BackendChoice,
    /// Track every selected cache again from its first frame, and write into cache folders that
    /// exist without a batch status file.
    #[arg(long)]
    pub force: bool,
    /// No progress bars and no per-cache lines; the table is still printed.
    #[arg(long, short)]
    pub quiet: bool,
    /// After tracking, carry data through each cache with these `surftrack propagate` arguments
    /// (one string, split at spaces), into OUTROOT/NAME/propagated: `--propagate '--forward --checker'`.
    #[arg(long, value_name = "ARGS", allow_hyphen_values = true)]
    pub propagate: Option<String>,
    /// After tracking, evaluate each cache against its input (`surftrack eval`'s defaults) into
    /// OUTROOT/NAME/eval.json.
    #[arg(long)]
    pub eval: bool,
    #[command(flatten)]
    pub params: MethodParams,
}

pub fn run(args: &BatchArgs) -> Result<(), CliError> {
    let manifest = Manifest::read(&args.manifest)?;
    if args.report {
        return report(&manifest, args);
    }
    let index = task_index(args.index, |name| std::env::var(name).ok())?;
    let selected: Vec<&Cache> = match index {
        Some(index) => vec![manifest.cache(index)?],
        None => manifest.caches.iter().collect(),
    };
    if let Some(text) = &args.propagate {
        // Checked once before any cache runs; each cache parses them again for its folder.
        PropagateArgs::for_batch(&args.out, text)?;
    }
    if !args.force {
        refuse_foreign_folders(&selected, args)?;
    }
    let backend = Backend::select(args.backend)?;
    std::fs::create_dir_all(&args.out).map_err(|source| CliError::CreateDir {
        path: args.out.clone(),
        source,
    })?;
    let jobs = args
        .jobs
        .unwrap_or_else(|| jobs::default_jobs(&selected))
        .clamp(1, selected.len());
    let request = Request {
        params: args.params.clone(),
        propagate: args.propagate.clone(),
        eval: args.eval,
    };
    let progress = BatchProgress::new(selected.len(), args.quiet);
    let context = CacheRun {
        root: &args.out,
        backend: &backend,
        request: &request,
        force: args.force,
        progress: &progress,
    };
    let outcomes = run_pool(&selected, jobs, &context);
    progress.finish();

    if index.is_some() {
        let outcome = &outcomes[0];
        print!("{}", table(std::slice::from_ref(&outcome.entry())));
        return match outcome.failure() {
            Some(error) => Err(CliError::CacheFailed {
                name: selected[0].name.clone(),
                error: error.to_string(),
            }),
            None => Ok(()),
        };
    }
    report(&manifest, args)
}

/// Tracks `caches` on `jobs` threads, each taking the next cache not yet begun; the outcomes come
/// back in the manifest's order, whichever thread ran them.
fn run_pool(caches: &[&Cache], jobs: usize, context: &CacheRun) -> Vec<Outcome> {
    let next = AtomicUsize::new(0);
    let mut outcomes: Vec<(usize, Outcome)> = std::thread::scope(|scope| {
        let workers: Vec<_> = (0..jobs)
            .map(|_| {
                scope.spawn(|| {
                    let mut ran = Vec::new();
                    loop {
                        let i = next.fetch_add(1, Ordering::Relaxed);
                        let Some(cache) = caches.get(i) else { break };
                        ran.push((i, context.run(cache)));
                    }
                    ran
                })
            })
            .collect();
        workers
            .into_iter()
            .flat_map(|worker| {
                worker
                    .join()
                    .unwrap_or_else(|panic| std::panic::resume_unwind(panic))
            })
            .collect()
    });
    outcomes.sort_by_key(|(i, _)| *i);
    outcomes.into_iter().map(|(_, outcome)| outcome).collect()
}

/// Refuses, before anything runs, to write into a cache folder the batch did not make (one that
/// exists, is not empty and has no status file): it is someone's output.
fn refuse_foreign_folders(caches: &[&Cache], args: &BatchArgs) -> Result<(), CliError> {
    for cache in caches {
        let dir = args.out.join(&cache.name);
        let not_empty = std::fs::read_dir(&dir).is_ok_and(|mut entries| entries.next().is_some());
        if not_empty && !dir.join(STATUS_FILE).exists() {
            return Err(CliError::ForeignCacheFolder { path: dir });
        }
    }
    Ok(())
}

/// Assembles, writes and prints the report; an error unless every cache is done.
fn report(manifest: &Manifest, args: &BatchArgs) -> Result<(), CliError> {
    let report = BatchReport::assemble(manifest, &args.out)?;
    let path = report.write(&args.out)?;
    print!("{}", report.table());
    println!("report: {}", path.display());
    if report.all_done() {
        Ok(())
    } else {
        Err(CliError::BatchUnfinished {
            failed: report.failed,
            unfinished: report.unfinished,
            total: report.caches.len(),
            report: path,
        })
    }
}
