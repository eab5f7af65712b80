//! The machine and the run, for the summary's header: CPU, cores, memory, OS, rustc, date and
//! load average.

use std::process::Command;
use std::time::SystemTime;

/// The machine and the run, for the report's header.
#[derive(Debug, Clone, PartialEq)]
pub struct RunInfo {
    /// CPU model.
    pub cpu: String,
    /// Logical cores.
    pub cores: usize,
    /// Memory (GiB).
    pub memory_gib: Option<f64>,
    /// Operating system and kernel.
    pub os: String,
    /// `rustc --version`.
    pub rustc: String,
    /// UTC date and time of the run.
    pub date: String,
    /// Load averages (1 min) at the start and the end of the run.
    pub load: (Option<f64>, Option<f64>),
    /// The command that ran the benches.
    pub command: String,
}

impl RunInfo {
    /// The machine, the run and the load on one line (for results files).
    pub fn one_line(&self) -> String {
        format!(
            "{}, {} logical cores{}; {}; {}; `{}`, {}{}",
            self.cpu,
            self.cores,
            self.memory_text(),
            self.os,
            self.rustc,
            self.command,
            self.date,
            self.load_text()
        )
    }

    /// `, 23.5 GiB`, or nothing when the memory is not known.
    pub fn memory_text(&self) -> String {
        self.memory_gib
            .map_or_else(String::new, |g| format!(", {g:.1} GiB"))
    }

    /// `; load average A at the start, B at the end`, or nothing when not known.
    pub fn load_text(&self) -> String {
        match self.load {
            (Some(a), Some(b)) => format!("; load average {a:.2} at the start, {b:.2} at the end"),
            _ => String::new(),
        }
    }
}

/// The CPU model from `lscpu`'s text ("Model name:") or `/proc/cpuinfo` ("model name").
pub fn cpu_model(lscpu: &str, cpuinfo: &str) -> Option<String> {
    let field = |text: &str, key: &str| {
        text.lines().find_map(|l| {
            let (k, v) = l.split_once(':')?;
            (k.trim() == key && !v.trim().is_empty()).then(|| v.trim().to_string())
        })
    };
    field(lscpu, "Model name").or_else(|| field(cpuinfo, "model name"))
}

/// `MemTotal` of `/proc/meminfo`, in GiB.
pub fn memory_gib(meminfo: &str) -> Option<f64> {
    let line = meminfo.lines().find(|l| l.starts_with("MemTotal:"))?;
    let kib: f64 = line
        .trim_start_matches("MemTotal:")
        .trim()
        .trim_end_matches("kB")
        .trim()
        .parse()
        .ok()?;
    Some(kib / (1024.0 * 1024.0))
}

/// Civil date (y, m, d) of a count of days since 1970-01-01 (proleptic Gregorian).
pub fn civil_from_days(days: i64) -> (i64, u32, u32) {
    let z = days + 719_468;
    let era = z.div_euclid(146_097);
    let doe = z.rem_euclid(146_097);
    let yoe = (doe - doe / 1460 + doe / 36_524 - doe / 146_096) / 365;
    let doy = doe - (365 * yoe + yoe / 4 - yoe / 100);
    let mp = (5 * doy + 2) / 153;
    let d = (doy - (153 * mp + 2) / 5 + 1) as u32;
    let m = if mp < 10 { mp + 3 } else { mp - 9 } as u32;
    let y = yoe + era * 400 + i64::from(m <= 2);
    (y, m, d)
}

/// `YYYY-MM-DD HH:MM UTC` of a time.
pub fn utc_string(t: SystemTime) -> String {
    let secs = t
        .duration_since(SystemTime::UNIX_EPOCH)
        .map(|d| d.as_secs() as i64)
        .unwrap_or(0);
    let (y, m, d) = civil_from_days(secs.div_euclid(86_400));
    let s = secs.rem_euclid(86_400);
    format!(
        "{y:04}-{m:02}-{d:02} {:02}:{:02} UTC",
        s / 3600,
        s % 3600 / 60
    )
}

pub fn load_average() -> Option<f64> {
    std::fs::read_to_string("/proc/loadavg")
        .ok()?
        .split_whitespace()
        .next()?
        .parse()
        .ok()
}

fn command_output(program: &str, args: &[&str]) -> Option<String> {
    let out = Command::new(program).args(args).output().ok()?;
    out.status
        .success()
        .then(|| String::from_utf8_lossy(&out.stdout).trim().to_string())
}

fn os_description() -> String {
    let pretty = std::fs::read_to_string("/etc/os-release")
        .ok()
        .and_then(|t| {
            t.lines()
                .find_map(|l| l.strip_prefix("PRETTY_NAME="))
                .map(|v| v.trim_matches('"').to_string())
        });
    let kernel = std::fs::read_to_string("/proc/sys/kernel/osrelease")
        .ok()
        .map(|k| k.trim().to_string());
    match (pretty, kernel) {
        (Some(p), Some(k)) => format!("{p}, Linux {k}"),
        (Some(p), None) => p,
        (None, Some(k)) => format!("Linux {k}"),
        (None, None) => std::env::consts::OS.to_string(),
    }
}

/// Describes this machine.
pub fn describe_machine(command: String, load_start: Option<f64>) -> RunInfo {
    let lscpu = command_output("lscpu", &[]).unwrap_or_default();
    let cpuinfo = std::fs::read_to_string("/proc/cpuinfo").unwrap_or_default();
    RunInfo {
        cpu: cpu_model(&lscpu, &cpuinfo).unwrap_or_else(|| "unknown CPU".to_string()),
        cores: std::thread::available_parallelism().map_or(1, |n| n.get()),
        memory_gib: std::fs::read_to_string("/proc/meminfo")
            .ok()
            .and_then(|m| memory_gib(&m)),
        os: os_description(),
        rustc: command_output("rustc", &["--version"]).unwrap_or_else(|| "rustc ?".to_string()),
        date: utc_string(SystemTime::now()),
        load: (load_start, load_average()),
        command,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::time::Duration;

    #[test]
    fn machine_fields() {
        let lscpu = "Architecture: x86_64\nModel name:                              AMD EPYC\n";
        assert_eq!(cpu_model(lscpu, "").as_deref(), Some("AMD EPYC"));
        let cpuinfo = "processor\t: 0\nmodel name\t: Intel(R) Xeon(R)\n";
        assert_eq!(cpu_model("", cpuinfo).as_deref(), Some("Intel(R) Xeon(R)"));
        assert_eq!(cpu_model("", ""), None);
        let gib = memory_gib("MemTotal:       24684084 kB\nMemFree: 1 kB\n").expect("mem");
        assert!((gib - 23.54).abs() < 0.01);
        assert_eq!(civil_from_days(0), (1970, 1, 1));
        assert_eq!(civil_from_days(11_016), (2000, 2, 29));
        assert_eq!(civil_from_days(20_413), (2025, 11, 21));
        let t = SystemTime::UNIX_EPOCH + Duration::from_secs(20_413 * 86_400 + 21 * 3600 + 5 * 60);
        assert_eq!(utc_string(t), "2025-11-21 21:05 UTC");
    }
}
