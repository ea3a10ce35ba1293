//! The `bumpsim` command line. Exit codes: 0 success, 2 bad config or input, 1 internal error.

use bumpsim_pipeline::animation;
use bumpsim_pipeline::config::{self, InputError};
use bumpsim_pipeline::output::{write_atomic, OutputSet};
use bumpsim_pipeline::plot;
use bumpsim_pipeline::run::{self, TraceRequest};
use bumpsim_pipeline::sweep;
use clap::{Parser, Subcommand, ValueEnum};
use std::path::PathBuf;
use std::process::ExitCode;

mod gates_cmd;
mod nv2a_cmd;
mod rtl_cmd;
mod rtl_top;

#[derive(Parser)]
#[command(
    name = "bumpsim",
    version,
    about = "Cycle-level, bit-accurate models of 1990s bump-mapping hardware"
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(clap::Args)]
struct ConfigArgs {
    /// A RON pipeline config (see configs/).
    config: PathBuf,
    /// Override a config field: --set path.to.field=value (repeatable).
    #[arg(long = "set", value_name = "PATH=VALUE")]
    sets: Vec<String>,
    /// Run past the up-front estimate of time and memory (10 minutes, 8 GiB on a 2-core,
    /// 24 GB machine); the hard limits of the fields still apply.
    #[arg(long)]
    force: bool,
}

impl ConfigArgs {
    fn load(&self) -> Result<config::Loaded, InputError> {
        let opts = config::LoadOptions { force: self.force };
        config::load_with(&self.config, &self.sets, opts)
    }
}

/// The longest trace window, in cycles.
const MAX_TRACE_CYCLES: u64 = 1_000_000;

#[derive(Subcommand)]
enum Command {
    /// Render a config: writes image.png, reference.png, error.png and report.json into DIR.
    Render {
        #[command(flatten)]
        args: ConfigArgs,
        #[arg(long)]
        out: PathBuf,
        /// Print each phase's wall time to stderr: scene and assets; paths (concurrent), with
        /// the overlapping wall times of its three paths under it (simulation, exact mode,
        /// reference); ROP; metrics; writing; and the total.
        #[arg(long)]
        timings: bool,
    },
    /// Run a config and print its report (a table, or JSON with --json).
    Report {
        #[command(flatten)]
        args: ConfigArgs,
        #[arg(long)]
        json: bool,
    },
    /// Write a cycle trace of a config's engine.
    Trace {
        #[command(flatten)]
        args: ConfigArgs,
        /// Half-open cycle window A..B.
        #[arg(long)]
        cycles: String,
        /// Comma-separated unit names (default: all).
        #[arg(long, value_delimiter = ',')]
        units: Option<Vec<String>>,
        #[arg(long, value_enum, default_value = "text")]
        format: TraceFormat,
        /// Trace frame K of the config's animation (`frames`; 0, the config itself, by
        /// default): its frame work is that frame's (the palette shaded for its light).
        #[arg(long, value_name = "K", default_value_t = 0)]
        frame: usize,
        #[arg(long)]
        out: PathBuf,
    },
    /// Run a sweep file: one report row per point in DIR/sweep.csv, sweep.jsonl and
    /// sweep.json (docs/sweep.md). With --merge, join shard directories into DIR.
    Sweep {
        /// A RON sweep file (see configs/sweeps/).
        #[arg(required_unless_present = "merge")]
        sweep: Option<PathBuf>,
        #[arg(long)]
        out: PathBuf,
        /// Run only the points whose index is i modulo n (0 <= i < n).
        #[arg(long, value_name = "i/n", conflicts_with = "merge")]
        shard: Option<String>,
        /// Join the rows of these shard directories (in point order) into --out; with the
        /// sweep file, check that they are its rows and draw its plots and tables.
        #[arg(long, num_args = 1.., value_name = "DIR")]
        merge: Vec<PathBuf>,
        /// Worker threads (default: RAYON_NUM_THREADS or one per core).
        #[arg(long)]
        threads: Option<usize>,
        /// Pass --force to every point's load.
        #[arg(long)]
        force: bool,
        /// Keep the rows of an earlier run in --out (its journal sweep.partial.jsonl and its
        /// sweep.jsonl) whose point is unchanged (same index and config hash), run the rest.
        #[arg(long, conflicts_with = "merge")]
        resume: bool,
    },
    /// Plot two numeric columns of a sweep's CSV as PNG or SVG (by --out's extension),
    /// the Pareto front of --pareto's objectives highlighted and its rows written to
    /// FILE.pareto.csv beside the plot (docs/sweep.md).
    Plot {
        /// A sweep's CSV (DIR/sweep.csv).
        csv: PathBuf,
        #[arg(long)]
        x: String,
        #[arg(long)]
        y: String,
        #[arg(long, value_enum, default_value = "scatter")]
        kind: PlotKind,
        /// Objectives of the front, each COLUMN:min or COLUMN:max, comma-separated, e.g.
        /// gates_total:min,total_psnr_db:max,cycles:min.
        #[arg(long, value_name = "OBJ,...")]
        pareto: Option<String>,
        /// The x axis' ends, LO,HI (default: the data's range with a margin); points beyond
        /// are drawn at the edge.
        #[arg(long, value_name = "LO,HI", allow_hyphen_values = true)]
        x_range: Option<String>,
        /// The y axis' ends, LO,HI.
        #[arg(long, value_name = "LO,HI", allow_hyphen_values = true)]
        y_range: Option<String>,
        /// A logarithmic x axis (rows with x not above 0 are skipped and counted).
        #[arg(long)]
        x_log: bool,
        /// A logarithmic y axis.
        #[arg(long)]
        y_log: bool,
        /// FILE.png or FILE.svg.
        #[arg(long)]
        out: PathBuf,
    },
    /// Print chosen columns of a sweep's CSV as a Markdown table, the rows filtered by
    /// --filter COLUMN=VALUE (docs/sweep.md).
    Table {
        /// A sweep's CSV (DIR/sweep.csv).
        csv: PathBuf,
        /// Columns, comma-separated.
        #[arg(long, value_name = "COL,...")]
        columns: String,
        /// Headings, comma-separated, one per column (default: the column names).
        #[arg(long, value_name = "TEXT,...")]
        headings: Option<String>,
        /// Keep only the rows whose COLUMN holds VALUE (repeatable: all must hold).
        #[arg(long, value_name = "COLUMN=VALUE")]
        filter: Vec<String>,
        /// Decimals of a non-integer number.
        #[arg(long, default_value_t = 2)]
        digits: u32,
        /// A cross table: one column per distinct value of OVER holding VALUE, the rows one
        /// per distinct combination of --columns.
        #[arg(long, value_name = "OVER=VALUE")]
        pivot: Option<String>,
    },
    /// Write study pages from their sources: each NAME.src.md (hand-written Markdown with
    /// directives that quote its sweeps' tables and cells and render its pictures) becomes
    /// NAME.md beside it (docs/studies.md).
    Study {
        /// Page sources, NAME.src.md.
        #[arg(required = true)]
        sources: Vec<PathBuf>,
        /// Read each sweep's rows already in its directory instead of running it, and render
        /// no pictures.
        #[arg(long)]
        reuse: bool,
        /// With --reuse: write nothing; exit 1 if a page differs from what its source and
        /// its sweeps' committed rows give.
        #[arg(long, requires = "reuse")]
        check: bool,
        /// Worker threads of the sweeps (default: one per core).
        #[arg(long)]
        threads: Option<usize>,
    },
    /// Validate a config (parse, scene, wiring) without rendering.
    Check {
        #[command(flatten)]
        args: ConfigArgs,
    },
    /// Print the engine's gate figures without rendering (the report's `gates`, the model's
    /// estimate, docs/gates.md); --synth adds the yosys synthesis of every unit with a
    /// Verilog generator beside them (docs/rtl.md).
    Gates {
        #[command(flatten)]
        args: ConfigArgs,
        #[arg(long)]
        synth: bool,
        #[arg(long)]
        json: bool,
    },
    /// Render NV2A frame configs (configs/nv2a/) and compare them with the frames real
    /// hardware rendered: per frame the pixels compared, the exact share, the largest
    /// difference and where the mismatches sit (docs/nv2a.md).
    Nv2a {
        /// NV2A frame configs (RON).
        #[arg(required = true)]
        frames: Vec<PathBuf>,
        /// Override a field of every frame: --set path.to.field=value (repeatable).
        #[arg(long = "set", value_name = "PATH=VALUE")]
        sets: Vec<String>,
        /// Run the units in exact (f64) mode instead of bit-accurate.
        #[arg(long)]
        exact: bool,
        /// Print the comparisons as JSON.
        #[arg(long)]
        json: bool,
        /// Write the model's picture of each frame (NAME.png), where it differs from the
        /// hardware's (NAME-diff.png: misses magenta) and nv2a.json into DIR.
        #[arg(long)]
        out: Option<PathBuf>,
    },
    /// Write Verilog of the engine's units into DIR (docs/rtl.md): NAME.v and NAME.regs per
    /// unit with a generator, and engine.v (the units wired as the config wires them) when
    /// every unit has one; --cosim N replays N vectors per unit and N fragments of the frame
    /// through engine.v with iverilog, --synth runs yosys.
    Rtl {
        #[command(flatten)]
        args: ConfigArgs,
        #[arg(long)]
        out: PathBuf,
        #[arg(long, default_value_t = 0, value_name = "N")]
        cosim: usize,
        #[arg(long)]
        synth: bool,
    },
}

#[derive(Clone, Copy, ValueEnum)]
enum PlotKind {
    Scatter,
    Line,
}

#[derive(Clone, Copy, ValueEnum)]
enum TraceFormat {
    Text,
    Vcd,
}

enum Failure {
    Input(InputError),
    Internal(String),
    /// Not an error of the input or of bumpsim: a check that found differences (exit 1).
    Check(String),
}

impl From<InputError> for Failure {
    fn from(e: InputError) -> Self {
        Failure::Input(e)
    }
}

fn parse_cycles(s: &str) -> Result<(u64, u64), InputError> {
    let bad = || {
        InputError::new(
            "--cycles",
            "",
            format!("{s:?}: expected A..B with A < B, e.g. 100..140"),
        )
    };
    let (a, b) = s.split_once("..").ok_or_else(bad)?;
    let (a, b): (u64, u64) = (
        a.trim().parse().map_err(|_| bad())?,
        b.trim().parse().map_err(|_| bad())?,
    );
    if a >= b {
        return Err(bad());
    }
    if b - a > MAX_TRACE_CYCLES {
        return Err(InputError::new(
            "--cycles",
            "",
            format!(
                "{s:?} is a window of {} cycles: a trace records at most {MAX_TRACE_CYCLES} \
                 cycles (expected B - A <= {MAX_TRACE_CYCLES}, e.g. {a}..{})",
                b - a,
                a.saturating_add(MAX_TRACE_CYCLES)
            ),
        ));
    }
    Ok((a, b))
}

fn execute(cmd: Command) -> Result<(), Failure> {
    match cmd {
        Command::Gates { args, synth, json } => gates_cmd::execute(&args.load()?, synth, json)?,
        Command::Rtl {
            args,
            out,
            cosim,
            synth,
        } => rtl_cmd::execute(&args.load()?, &out, cosim, synth)?,
        Command::Nv2a {
            frames,
            sets,
            exact,
            json,
            out,
        } => nv2a_cmd::execute(&frames, &sets, exact, json, out.as_deref())?,
        Command::Render { args, out, timings } => {
            let l = args.load()?;
            let animation = animation::run(&l)?;
            let mut r = animation.first;
            let mut set = OutputSet::new(&out);
            // frame k > 0 of an animation: its bit-accurate image as frame-k.png
            let names: Vec<String> = (1..=animation.images.len())
                .map(|k| format!("frame-{k:03}.png"))
                .collect();
            let mut pngs = vec![
                ("image.png", &r.image),
                ("reference.png", &r.reference),
                ("error.png", &r.error),
            ];
            pngs.extend(names.iter().map(String::as_str).zip(&animation.images));
            set.add_pngs(&pngs).map_err(Failure::Internal)?;
            set.add("report.json", r.report.to_json().into_bytes());
            set.commit().map_err(|e| {
                Failure::Input(InputError::new(out.display().to_string(), "--out", e))
            })?;
            r.timings.lap("writing");
            if timings {
                eprint!("phase wall times:\n{}", r.timings.to_text());
            }
            print!("{}", r.report.to_table());
            let frames = match names.len() {
                0 => String::new(),
                n => format!(", frame-001..{n:03}.png"),
            };
            println!(
                "\nwrote {}/{{image,reference,error}}.png{frames} and report.json",
                out.display()
            );
        }
        Command::Report { args, json } => {
            let l = args.load()?;
            let r = animation::run(&l)?.first;
            if json {
                print!("{}", r.report.to_json());
            } else {
                print!("{}", r.report.to_table());
            }
        }
        Command::Trace {
            args,
            cycles,
            units,
            format,
            frame,
            out,
        } => {
            let cycles = parse_cycles(&cycles)?;
            let l = config::frames::frame(&args.load()?, frame)?;
            let req = TraceRequest { cycles, units };
            let r = run::run(&l, Some(&req))?;
            let trace = r
                .trace
                .ok_or_else(|| Failure::Internal("no trace was recorded".into()))?;
            let bytes = match format {
                TraceFormat::Text => trace.to_text().into_bytes(),
                TraceFormat::Vcd => {
                    let mut v = Vec::new();
                    trace
                        .write_vcd(&mut v)
                        .map_err(|e| Failure::Internal(e.to_string()))?;
                    v
                }
            };
            write_atomic(&out, &bytes).map_err(|e| {
                Failure::Input(InputError::new(out.display().to_string(), "--out", e))
            })?;
            println!("wrote {} ({} records)", out.display(), trace.records.len());
        }
        Command::Sweep {
            sweep,
            out,
            shard,
            merge,
            threads,
            force,
            resume,
        } => {
            let out_err =
                |e: String| Failure::Input(InputError::new(out.display().to_string(), "--out", e));
            if !merge.is_empty() {
                let dirs: Vec<&std::path::Path> = merge.iter().map(|d| d.as_path()).collect();
                let files = sweep::merge(&dirs)
                    .map_err(|e| Failure::Input(InputError::new("--merge", "", e)))?;
                let s = sweep.as_deref().map(sweep::load).transpose()?;
                let csv = files
                    .iter()
                    .find(|f| f.0 == "sweep.csv")
                    .map(|f| String::from_utf8_lossy(&f.1).into_owned())
                    .unwrap_or_default();
                if let (Some(s), Some(path)) = (&s, &sweep) {
                    s.check_merged(&csv).map_err(|e| {
                        Failure::Input(InputError::new(path.display().to_string(), "--merge", e))
                    })?;
                }
                let mut set = OutputSet::new(&out);
                for (name, bytes) in files {
                    set.add(name, bytes);
                }
                set.commit().map_err(out_err)?;
                println!(
                    "merged {} shards; wrote {}/sweep.{{csv,jsonl,json}}",
                    merge.len(),
                    out.display()
                );
                if let Some(s) = &s {
                    draw_sweep(s, &csv, &out);
                }
            } else {
                let path = sweep.expect("clap requires a sweep file without --merge");
                let shard = shard.as_deref().map(sweep::Shard::parse).transpose()?;
                if threads == Some(0) {
                    return Err(Failure::Input(InputError::new(
                        "--threads",
                        "",
                        "0: expected at least one thread",
                    )));
                }
                let s = sweep::load(&path)?;
                let opts = sweep::RunOptions {
                    shard,
                    force,
                    threads,
                };
                let o = sweep::run_into(&s, &out, opts, resume).map_err(|e| match e {
                    sweep::DirError::Input(e) => Failure::Input(e),
                    sweep::DirError::Internal(e) => Failure::Internal(e),
                })?;
                if o.replaced_journal {
                    eprintln!(
                        "note: replaced the journal of an earlier run in {} (--resume keeps its rows)",
                        out.display()
                    );
                }
                if let Some(e) = &o.journal_failure {
                    eprintln!("warning: the journal stopped (the sweep went on): {e}");
                }
                if resume {
                    println!(
                        "resume: {} points kept from {}, {} earlier rows run again (their point \
                         changed in the sweep file, or they were errors)",
                        o.kept,
                        out.display(),
                        o.stale
                    );
                }
                let bad = o.errors;
                println!(
                    "{} of {} points run, {} with errors; wrote {}/sweep.{{csv,jsonl,json}}",
                    o.ran,
                    o.points,
                    bad,
                    out.display()
                );
                if shard.is_some() {
                    if !(s.file.plots.is_empty() && s.file.tables.is_empty()) {
                        println!(
                            "plots and tables: not drawn from a shard's rows (`bumpsim sweep \
                             {} --merge SHARD_DIRS... --out DIR` draws them from all rows)",
                            path.display()
                        );
                    }
                } else if !(s.file.plots.is_empty() && s.file.tables.is_empty()) {
                    // the rows went to the file as they came: read back for the drawing
                    match std::fs::read_to_string(out.join("sweep.csv")) {
                        Ok(csv) => draw_sweep(&s, &csv, &out),
                        Err(e) => eprintln!("warning: plots and tables not drawn: {e}"),
                    }
                }
            }
        }
        Command::Plot {
            csv,
            x,
            y,
            kind,
            pareto,
            x_range,
            y_range,
            x_log,
            y_log,
            out,
        } => {
            let scale = |flag: &str, range: Option<String>, log: bool| {
                let range = match range {
                    None => None,
                    Some(r) => {
                        let v: Vec<Option<f64>> =
                            r.split(',').map(|t| t.trim().parse::<f64>().ok()).collect();
                        match v[..] {
                            [Some(lo), Some(hi)] => Some((lo, hi)),
                            _ => {
                                let m = format!("{r:?}: expected LO,HI, two numbers");
                                return Err(InputError::new(flag, "", m));
                            }
                        }
                    }
                };
                let s = plot::axis::Scale { range, log };
                s.check().map_err(|m| InputError::new(flag, "", m))?;
                Ok(s)
            };
            let x_scale = scale("--x-range", x_range, x_log)?;
            let y_scale = scale("--y-range", y_range, y_log)?;
            let objectives = match &pareto {
                Some(p) => plot::pareto::Objective::parse_list(p)
                    .map_err(|e| InputError::new("--pareto", "", e))?,
                None => Vec::new(),
            };
            let req = plot::Request {
                x,
                y,
                kind: match kind {
                    PlotKind::Scatter => plot::Kind::Scatter,
                    PlotKind::Line => plot::Kind::Line,
                },
                objectives,
                x_scale,
                y_scale,
            };
            let table = plot::read_csv(&csv)?;
            let p = plot::prepare(&table, &csv.display().to_string(), &req)?;
            let written = plot::write(&p, &out)?;
            let names: Vec<String> = written.iter().map(|w| w.display().to_string()).collect();
            println!("{}; wrote {}", p.summary(), names.join(" and "));
        }
        Command::Table {
            csv,
            columns,
            headings,
            filter,
            digits,
            pivot,
        } => {
            let list = |s: &str| s.split(',').map(|c| c.trim().to_string()).collect();
            let pivot = match pivot.as_deref().map(|p| p.split_once('=')) {
                None => None,
                Some(Some((over, value))) => Some(plot::table::Pivot {
                    over: over.trim().into(),
                    value: value.trim().into(),
                    headings: Vec::new(),
                }),
                Some(None) => {
                    return Err(InputError::new(
                        "--pivot",
                        "",
                        "expected OVER=VALUE: the column to spread and the cell to show",
                    )
                    .into())
                }
            };
            let spec = plot::table::TableSpec {
                name: String::new(),
                columns: list(&columns),
                headings: headings.as_deref().map(list).unwrap_or_default(),
                filter,
                digits,
                pivot,
                ..Default::default()
            };
            let table = plot::read_csv(&csv)?;
            print!("{}", spec.markdown(&table, &csv.display().to_string(), "")?);
        }
        Command::Study {
            sources,
            reuse,
            check,
            threads,
        } => {
            use bumpsim_pipeline::study;
            let opts = study::Options { reuse, threads };
            let mut stale = Vec::new();
            for src in &sources {
                let page = study::page_of(src)?;
                let made = study::expand(src, opts)?;
                if check {
                    let old = std::fs::read_to_string(&page).unwrap_or_default();
                    if old != made.text {
                        stale.push(page.display().to_string());
                    }
                    continue;
                }
                for p in made.write(&page)? {
                    println!("wrote {}", p.display());
                }
            }
            if !stale.is_empty() {
                return Err(Failure::Check(format!(
                    "not what their sources give (run `bumpsim study` on them): {}",
                    stale.join(", ")
                )));
            }
        }
        Command::Check { args } => {
            let l = args.load()?;
            let scene = run::build_scene(&l)?;
            bumpsim_pipeline::engine::build(&l, &scene)?;
            println!(
                "ok: {} ({} triangles, {} units, hash {})",
                l.config.name,
                scene.mesh.triangles.len(),
                l.config.engine.units.len(),
                &l.hash[..16]
            );
        }
    }
    Ok(())
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    let outcome = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| execute(cli.command)));
    match outcome {
        Ok(Ok(())) => ExitCode::SUCCESS,
        Ok(Err(Failure::Input(e))) => {
            eprintln!("error: {e}");
            ExitCode::from(2)
        }
        Ok(Err(Failure::Check(e))) => {
            eprintln!("{e}");
            ExitCode::from(1)
        }
        Ok(Err(Failure::Internal(e))) => {
            eprintln!("internal error: {e}");
            ExitCode::from(1)
        }
        Err(_) => {
            eprintln!("internal error: bumpsim panicked (a bug: please report it with the config)");
            ExitCode::from(1)
        }
    }
}

/// The plots and tables of sweep `s` from its rows (`csv`) into `out`. The rows are written
/// already: a plot or table that cannot be drawn from them (no numeric values, every point
/// an error) is a warning, not a failure of the sweep.
fn draw_sweep(s: &sweep::Sweep, csv: &str, out: &std::path::Path) {
    if !s.file.plots.is_empty() {
        match plot::sweep_plots(&s.file.plots, csv, out) {
            Ok(lines) => lines.iter().for_each(|l| println!("plot: {l}")),
            Err(e) => eprintln!("warning: plots not drawn: {e}"),
        }
    }
    if !s.file.tables.is_empty() {
        match plot::table::sweep_tables(&s.file.tables, csv, out) {
            Ok(lines) => lines.iter().for_each(|l| println!("table: {l}")),
            Err(e) => eprintln!("warning: tables not written: {e}"),
        }
    }
}
