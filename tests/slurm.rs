//! A phase study on a real Slurm scheduler: `tools/slurm/phase_array.sh` submits a 4-task job
//! array (one shard each) and a merge job depending on it to a one-node Slurm started here on
//! localhost, and the merged `phase.csv` must equal a single-machine run cell for cell (every
//! column but the wall time).
//!
//! Where it runs. As root, the test installs Debian's `slurm-wlm` and `munge` with apt-get
//! when their binaries are missing (`apt-get update` first) and starts `munged` unless one
//! already answers. As another user it runs only when Slurm is already installed and a
//! `munged` already answers `munge -n | unmunge` (the daemons then run as that user). It
//! starts `slurmctld` and `slurmd` in the foreground as its own children, on free ports, with
//! every state, spool, log and pid file in a scratch directory.
//!
//! Where it cannot run (not root and Slurm or munge missing, or the install failed), it
//! prints one line `slurm test SKIPPED: <why>` to the terminal and passes, so
//! `cargo test --release` on a laptop stays green. With `SLITHER_REQUIRE_SLURM=1` in the
//! environment (CI sets it in `.ci/run`) a skip is a failure instead. Once the scheduler is
//! available, nothing skips: a daemon that does not start or a job that does not finish within
//! its timeout fails the test with the daemon and job logs. The daemons it started are stopped
//! by their process ids when it ends (also on failure).
//!
//! Timeouts (generous for a loaded 2-core machine; the whole test takes seconds when Slurm is
//! installed): [`NODE_TIMEOUT`] for the node to come up idle, [`JOBS_TIMEOUT`] for the array
//! and the merge job to leave the queue.

mod common;
/// The tiny S-start of `tests/phase.rs`: cells take milliseconds, so the test measures the
/// scheduler plumbing, not the physics.
use common::TINY_S_START as BASE;
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Output, Stdio};
use std::time::{Duration, Instant};

const BIN: &str = env!("CARGO_BIN_EXE_slither");
const SCRIPT: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/tools/slurm/phase_array.sh");

/// Longest wait for the one node to register with the controller and report idle.
const NODE_TIMEOUT: Duration = Duration::from_secs(60);
/// Longest wait for the array tasks and the merge job to leave the queue.
const JOBS_TIMEOUT: Duration = Duration::from_secs(240);

/// The Slurm and munge programs the test needs (searched on PATH, /usr/sbin and /usr/bin).
const PROGRAMS: [&str; 8] = [
    "munged",
    "munge",
    "unmunge",
    "slurmctld",
    "slurmd",
    "sbatch",
    "squeue",
    "sinfo",
];

fn find(program: &str) -> Option<PathBuf> {
    let path = std::env::var("PATH").unwrap_or_default();
    let found = path
        .split(':')
        .chain(["/usr/sbin", "/usr/bin", "/sbin", "/bin"])
        .map(|d| Path::new(d).join(program))
        .find(|p| p.is_file());
    found
}

fn prog(program: &str) -> PathBuf {
    find(program).unwrap_or_else(|| panic!("{program} not found after installing Slurm"))
}

fn text(o: &Output) -> String {
    format!(
        "status {}\nstdout:\n{}\nstderr:\n{}",
        o.status,
        String::from_utf8_lossy(&o.stdout),
        String::from_utf8_lossy(&o.stderr)
    )
}

fn is_root() -> bool {
    Command::new("id")
        .arg("-u")
        .output()
        .map(|o| String::from_utf8_lossy(&o.stdout).trim() == "0")
        .unwrap_or(false)
}

/// The user the test runs as (`id -un`); the Slurm daemons run as this user.
fn user() -> String {
    Command::new("id")
        .arg("-un")
        .output()
        .map(|o| String::from_utf8_lossy(&o.stdout).trim().to_string())
        .ok()
        .filter(|u| !u.is_empty())
        .unwrap_or_else(|| "root".to_string())
}

/// Whether a running munged answers: `munge -n | unmunge` succeeds.
fn munge_works() -> bool {
    let (Some(munge), Some(unmunge)) = (find("munge"), find("unmunge")) else {
        return false;
    };
    let m = Command::new(munge)
        .arg("-n")
        .stdout(Stdio::piped())
        .stderr(Stdio::null())
        .spawn();
    let Ok(mut m) = m else { return false };
    let ok = Command::new(unmunge)
        .stdin(m.stdout.take().unwrap())
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .status()
        .is_ok_and(|s| s.success());
    let _ = m.wait();
    ok
}

/// The variable that turns a skip into a failure (CI sets it).
const REQUIRE: &str = "SLITHER_REQUIRE_SLURM";

/// Make the scheduler's programs available: `Ok` when the test can run, `Err(why)` when it
/// cannot (apt-get as root when programs are missing; idempotent).
fn availability() -> Result<(), String> {
    let missing: Vec<&str> = PROGRAMS
        .iter()
        .copied()
        .filter(|p| find(p).is_none())
        .collect();
    let root = is_root();
    if !root {
        if !missing.is_empty() {
            return Err(format!(
                "not root and Slurm is not installed (missing {}); run as root, or install \
                 slurm-wlm and munge and start munged",
                missing.join(", ")
            ));
        }
        if !munge_works() {
            return Err(
                "not root and no munged answers `munge -n | unmunge`; start munged \
                        (as root) or run the test as root"
                    .to_string(),
            );
        }
        return Ok(());
    }
    if missing.is_empty() {
        return Ok(());
    }
    let t = Instant::now();
    for args in [
        &["update"][..],
        &["install", "-y", "slurm-wlm", "munge"][..],
    ] {
        let o = Command::new("apt-get")
            .args(args)
            .env("DEBIAN_FRONTEND", "noninteractive")
            .output()
            .map_err(|e| format!("Slurm is missing and apt-get cannot run: {e}"))?;
        if !o.status.success() {
            let err = String::from_utf8_lossy(&o.stderr);
            let last = err
                .lines()
                .rev()
                .find(|l| !l.trim().is_empty())
                .unwrap_or("");
            return Err(format!(
                "Slurm is missing and `apt-get {}` failed ({}: {last})",
                args.join(" "),
                o.status
            ));
        }
    }
    eprintln!(
        "installed slurm-wlm and munge in {:.0} s",
        t.elapsed().as_secs_f64()
    );
    match PROGRAMS.iter().find(|p| find(p).is_none()) {
        Some(p) => Err(format!(
            "{p} not found after installing slurm-wlm and munge"
        )),
        None => Ok(()),
    }
}

/// Whether to run: `true` when the scheduler is available. Otherwise one line on the terminal
/// (written past the test harness's capture, so it shows in a passing run) and `false`, or a
/// failure when [`REQUIRE`] is `1`.
fn should_run() -> bool {
    let Err(why) = availability() else {
        return true;
    };
    if std::env::var(REQUIRE).is_ok_and(|v| v == "1") {
        panic!("{REQUIRE}=1 but the Slurm test cannot run: {why}");
    }
    use std::io::Write;
    let _ = writeln!(
        std::io::stderr().lock(),
        "slurm test SKIPPED: {why} (set {REQUIRE}=1 to make this a failure)"
    );
    false
}

/// A free TCP port on localhost (bound, read and released).
fn free_port() -> u16 {
    std::net::TcpListener::bind("127.0.0.1:0")
        .and_then(|l| l.local_addr())
        .expect("a free port")
        .port()
}

fn read(path: &Path) -> String {
    std::fs::read_to_string(path).unwrap_or_else(|e| format!("({}: {e})", path.display()))
}

/// The daemons this test started; dropping it stops them by process id.
struct Scheduler {
    dir: PathBuf,
    conf: PathBuf,
    children: Vec<(&'static str, Child)>,
    /// munged's pid when this test started it (a munged already running is left alone).
    munged: Option<u32>,
}

impl Scheduler {
    /// Every daemon log and what the queue says, for a failure message.
    fn logs(&self) -> String {
        let mut s = String::new();
        for name in [
            "slurmctld.log",
            "slurmd.log",
            "slurmctld.out",
            "slurmd.out",
            "munged.out",
        ] {
            s += &format!("==== {name}\n{}\n", read(&self.dir.join(name)));
        }
        s += &format!(
            "==== munged.log\n{}\n",
            read(Path::new("/var/log/munge/munged.log"))
        );
        s
    }

    fn cmd(&self, program: &str) -> Command {
        let mut c = Command::new(prog(program));
        c.env("SLURM_CONF", &self.conf);
        c
    }

    fn start() -> Scheduler {
        let dir = PathBuf::from(env!("CARGO_TARGET_TMPDIR"))
            .join(format!("slurm-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        for d in ["state", "spool"] {
            std::fs::create_dir_all(dir.join(d)).unwrap();
        }
        let mut s = Scheduler {
            conf: dir.join("slurm.conf"),
            dir,
            children: Vec::new(),
            munged: None,
        };
        s.start_munge();
        let host = String::from_utf8(Command::new("hostname").arg("-s").output().unwrap().stdout)
            .unwrap()
            .trim()
            .to_string();
        let cpus = std::thread::available_parallelism().map_or(1, |n| n.get());
        let d = s.dir.display();
        let (ctld_port, d_port) = (free_port(), free_port());
        let user = user();
        let conf = format!(
            "ClusterName=slithertest\n\
             SlurmctldHost={host}\n\
             SlurmctldPort={ctld_port}\n\
             SlurmdPort={d_port}\n\
             SlurmUser={user}\n\
             SlurmdUser={user}\n\
             AuthType=auth/munge\n\
             StateSaveLocation={d}/state\n\
             SlurmdSpoolDir={d}/spool\n\
             SlurmctldPidFile={d}/slurmctld.pid\n\
             SlurmdPidFile={d}/slurmd.pid\n\
             SlurmctldLogFile={d}/slurmctld.log\n\
             SlurmdLogFile={d}/slurmd.log\n\
             ProctrackType=proctrack/linuxproc\n\
             TaskPlugin=task/none\n\
             JobAcctGatherType=jobacct_gather/none\n\
             SelectType=select/cons_tres\n\
             SelectTypeParameters=CR_Core\n\
             SchedulerType=sched/backfill\n\
             MpiDefault=none\n\
             ReturnToService=2\n\
             NodeName={host} CPUs={cpus} RealMemory=500 State=UNKNOWN\n\
             PartitionName=test Nodes={host} Default=YES MaxTime=INFINITE State=UP\n"
        );
        std::fs::write(&s.conf, conf).unwrap();
        for (name, program, extra) in [
            ("slurmctld", "slurmctld", &["-i"][..]),
            ("slurmd", "slurmd", &[][..]),
        ] {
            let out = std::fs::File::create(s.dir.join(format!("{name}.out"))).unwrap();
            let child = Command::new(prog(program))
                .args(["-D", "-f", s.conf.to_str().unwrap()])
                .args(extra)
                .env("SLURM_CONF", &s.conf)
                .stdout(out.try_clone().unwrap())
                .stderr(out)
                .spawn()
                .unwrap_or_else(|e| panic!("cannot start {program}: {e}"));
            s.children.push((name, child));
            if name == "slurmctld" {
                std::thread::sleep(Duration::from_millis(500));
            }
        }
        s.wait_idle();
        s
    }

    /// Start munged as the `munge` user unless a running one already answers `munge -n`.
    fn start_munge(&mut self) {
        let works = munge_works;
        if works() {
            return;
        }
        let run = Path::new("/run/munge");
        std::fs::create_dir_all(run).unwrap();
        let _ = Command::new("chown")
            .args(["munge:munge", "/run/munge"])
            .status();
        let out = std::fs::File::create(self.dir.join("munged.out")).unwrap();
        let o = Command::new("runuser")
            .args(["-u", "munge", "--"])
            .arg(prog("munged"))
            .arg("--force")
            .stdout(out.try_clone().unwrap())
            .stderr(out)
            .status()
            .expect("runuser runs");
        assert!(o.success(), "munged did not start:\n{}", self.logs());
        // munged daemonises; its pid file names the process to stop afterwards.
        let deadline = Instant::now() + Duration::from_secs(10);
        loop {
            let pid = std::fs::read_to_string(run.join("munged.pid"))
                .ok()
                .and_then(|s| s.trim().parse::<u32>().ok());
            if let (Some(pid), true) = (pid, works()) {
                self.munged = Some(pid);
                return;
            }
            assert!(
                Instant::now() < deadline,
                "munged started but `munge -n | unmunge` fails:\n{}",
                self.logs()
            );
            std::thread::sleep(Duration::from_millis(200));
        }
    }

    /// Wait until the node reports idle; fail with the daemon logs otherwise.
    fn wait_idle(&mut self) {
        let deadline = Instant::now() + NODE_TIMEOUT;
        let mut last = String::new();
        while Instant::now() < deadline {
            let exited = self
                .children
                .iter_mut()
                .find_map(|(name, c)| c.try_wait().ok().flatten().map(|st| (*name, st)));
            if let Some((name, st)) = exited {
                panic!("{name} exited ({st}) while starting:\n{}", self.logs());
            }
            if let Ok(o) = self.cmd("sinfo").args(["-h", "-N", "-o", "%T"]).output() {
                last = text(&o);
                if o.status.success() && String::from_utf8_lossy(&o.stdout).trim() == "idle" {
                    return;
                }
            }
            std::thread::sleep(Duration::from_millis(500));
        }
        panic!(
            "the Slurm node did not become idle within {NODE_TIMEOUT:?} (last sinfo: {last}):\n{}",
            self.logs()
        );
    }
}

impl Drop for Scheduler {
    fn drop(&mut self) {
        for (_, c) in self.children.iter_mut().rev() {
            let _ = Command::new("kill")
                .args(["-TERM", &c.id().to_string()])
                .status();
            let deadline = Instant::now() + Duration::from_secs(10);
            while Instant::now() < deadline {
                if let Ok(Some(_)) = c.try_wait() {
                    break;
                }
                std::thread::sleep(Duration::from_millis(100));
            }
            if !matches!(c.try_wait(), Ok(Some(_))) {
                let _ = c.kill();
                let _ = c.wait();
            }
        }
        if let Some(pid) = self.munged {
            let _ = Command::new("kill")
                .args(["-TERM", &pid.to_string()])
                .status();
        }
    }
}

/// Rows of a `phase.csv` keyed by `(W, G)`, without the wall-time column.
fn rows(csv: &Path) -> std::collections::BTreeMap<(String, String), String> {
    let text = std::fs::read_to_string(csv).unwrap();
    let header: Vec<&str> = text.lines().next().unwrap().split(',').collect();
    let wall = header.iter().position(|h| *h == "wall_time_s").unwrap();
    text.lines()
        .skip(1)
        .map(|l| {
            let mut f: Vec<&str> = l.split(',').collect();
            f[wall] = "";
            ((f[0].to_string(), f[1].to_string()), f.join(","))
        })
        .collect()
}

#[test]
fn job_array_on_one_node_slurm_merges_to_the_single_machine_run() {
    let t0 = Instant::now();
    if !should_run() {
        return;
    }
    let dir = PathBuf::from(env!("CARGO_TARGET_TMPDIR"))
        .join(format!("slurm-study-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::write(dir.join("base.toml"), BASE).unwrap();
    let file = dir.join("phase.toml");
    std::fs::write(
        &file,
        "[phase]\nbase = \"base.toml\"\nweight = { from = 100.0, to = 1e4, count = 3 }\n\
         torque = [10.0, 20.0]\n",
    )
    .unwrap();

    // The single-machine reference.
    let whole = dir.join("whole");
    let o = Command::new(BIN)
        .args([
            "phase",
            file.to_str().unwrap(),
            "--out",
            whole.to_str().unwrap(),
            "--quiet",
        ])
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", text(&o));
    let reference = rows(&whole.join("phase.csv"));
    assert_eq!(reference.len(), 6);

    let sched = Scheduler::start();
    let t_up = t0.elapsed();
    let out = dir.join("cluster");
    let o = Command::new("bash")
        .arg(SCRIPT)
        .args([file.to_str().unwrap(), out.to_str().unwrap(), "4"])
        .env("SLITHER", BIN)
        .env("SLURM_CONF", &sched.conf)
        .env(
            "PATH",
            format!(
                "{}:{}",
                prog("sbatch").parent().unwrap().display(),
                std::env::var("PATH").unwrap_or_default()
            ),
        )
        .output()
        .unwrap();
    assert!(
        o.status.success(),
        "submission failed:\n{}\n{}",
        text(&o),
        sched.logs()
    );
    let ids = String::from_utf8_lossy(&o.stdout).to_string();
    let id = |what: &str| {
        ids.lines()
            .find_map(|l| l.strip_prefix(what))
            .and_then(|s| s.trim().parse::<u64>().ok())
            .unwrap_or_else(|| panic!("no `{what}JOBID` line in the script's output: {ids}"))
    };
    let (array, merge) = (id("array "), id("merge "));
    assert!(merge > array, "{ids}");

    // Wait for the queue to drain.
    let deadline = Instant::now() + JOBS_TIMEOUT;
    let job_logs = || {
        let mut s = String::new();
        if let Ok(rd) = std::fs::read_dir(out.join("logs")) {
            for e in rd.flatten() {
                s += &format!("==== {}\n{}\n", e.path().display(), read(&e.path()));
            }
        }
        s
    };
    loop {
        let q = sched
            .cmd("squeue")
            .args(["-h", "-o", "%i %T %r"])
            .output()
            .unwrap();
        assert!(
            q.status.success(),
            "squeue failed:\n{}\n{}",
            text(&q),
            sched.logs()
        );
        let queue = String::from_utf8_lossy(&q.stdout).trim().to_string();
        if queue.is_empty() {
            break;
        }
        assert!(
            Instant::now() < deadline,
            "jobs still queued after {JOBS_TIMEOUT:?}:\n{queue}\n{}\n{}",
            job_logs(),
            sched.logs()
        );
        std::thread::sleep(Duration::from_millis(500));
    }
    let t_jobs = t0.elapsed();

    // Four shards, each with its own share of the cells, and the merged result.
    let mut cells = 0;
    for i in 1..=4 {
        let csv = out.join(format!("shard_{i}/phase.csv"));
        assert!(
            csv.exists(),
            "shard {i} wrote no phase.csv:\n{}\n{}",
            job_logs(),
            sched.logs()
        );
        let r = rows(&csv);
        for (k, row) in &r {
            assert_eq!(reference.get(k), Some(row), "shard {i} cell {k:?}");
        }
        cells += r.len();
    }
    assert_eq!(cells, 6, "every cell in exactly one of the 4 shards");
    let merged = out.join("merged");
    assert!(
        merged.join("phase.csv").exists(),
        "the merge job wrote nothing:\n{}\n{}",
        job_logs(),
        sched.logs()
    );
    assert_eq!(rows(&merged.join("phase.csv")), reference);
    for f in ["phase.png", "boundaries.json", "writhe_vs_ratio.png"] {
        assert!(merged.join(f).exists(), "{f} not merged");
    }
    drop(sched);
    eprintln!(
        "slurm test: scheduler up after {:.1} s, jobs done after {:.1} s, total {:.1} s",
        t_up.as_secs_f64(),
        t_jobs.as_secs_f64(),
        t0.elapsed().as_secs_f64()
    );
}
