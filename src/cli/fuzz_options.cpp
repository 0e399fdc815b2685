#include "cli/fuzz_options.hpp"

#include "cli/client_options.hpp"
#include "cli/tls_options.hpp"

namespace mblab::cli {

void add_fuzz_options(CLI::App& cmd, FuzzCommandOptions& options) {
    cmd.add_option("target", options.target,
                   "tcp://HOST[:PORT], mbaps://HOST[:PORT] (with --cert, --key, --ca), "
                   "rtu:///DEV?baud=N, ascii:///DEV?baud=N or rtu+tcp://HOST:PORT")
        ->required();
    cmd.add_option("--seed", options.seed, "seed of the mutations: the same seed, the same run")
        ->capture_default_str();
    cmd.add_option("--cases", options.cases, "case budget (0: the --duration budget alone)")
        ->capture_default_str();
    accept_duration_units(cmd.add_option("--duration", options.duration,
                                         "time budget: 30s, 10m (a number alone is seconds; "
                                         "0: the case budget alone)")
                              ->check(CLI::NonNegativeNumber),
                          DurationUnit::seconds, false);
    cmd.add_option("--rate", options.rate, "sends per second at most (0: no limit)")
        ->check(CLI::NonNegativeNumber)
        ->capture_default_str();
    cmd.add_option("--check-every", options.check_every, "the liveness check after every N cases")
        ->check(CLI::Range(1, 100000))
        ->capture_default_str();
    add_duration_option(cmd, "--timeout", options.timeout_ms,
                        "how long the liveness check waits for its answer: "
                        "milliseconds, or 250ms, 2s",
                        DurationUnit::milliseconds, CLI::Range(1, 600000));
    cmd.add_option("--unit", options.unit, "unit identifier of the device (default 1)")
        ->check(CLI::Range(0, 255));
    cmd.add_option("--dut", options.dut_file,
                   "TOML file declaring the device (unit, max_read), as for mblab conform")
        ->check(CLI::ExistingFile);
    cmd.add_option("--learn", options.learn,
                   "learn the reconnaissance from FILE, a pcap or pcapng capture of normal "
                   "traffic to the target's port, instead of probing")
        ->check(CLI::ExistingFile);
    cmd.add_option("--writable", options.writable,
                   "START:COUNT: holding registers and coils the cases may write (default: "
                   "none)");
    cmd.add_flag("--allow-writes", options.allow_writes,
                 "writes anywhere: only for a lab device whose data does not matter");
    cmd.add_option("--restart", options.restart,
                   "shell command that restarts the device: a finding is then minimised");
    cmd.add_option("--replay", options.replay,
                   "send a reproducer's frames instead of fuzzing, then check liveness");
    cmd.add_option("--reproducer", options.files.reproducer,
                   "where the first finding's reproducer (hex lines) is written, FILE.pcapng "
                   "too (default: finding-1.hex in the report directory)");
    cmd.add_option("--report-dir", options.report_dir,
                   "directory for the findings' reproducers and report.json (default: a new one "
                   "under $XDG_STATE_HOME/mblab/fuzz, or /tmp/mblab-fuzz-XXXXXX)");
    cmd.add_flag("--keep-going", options.keep_going,
                 "record every finding instead of stopping at the first (the device is "
                 "restarted with --restart, or waited for, after each)");
    cmd.add_option("--monitor", options.monitor.spec,
                   "essential-function monitor beside the run, on its own connection: "
                   "register=N,period=MS,budget=MS,miss=PERCENT (FC 06 then FC 03 read-back; "
                   "read-only: FC 03 alone); judged PASS, DEGRADED or FAIL");
    accept_duration_units(cmd.add_option("--baseline", options.monitor.baseline_s,
                                         "how long the monitor runs alone first (default 2s)")
                              ->check(CLI::NonNegativeNumber),
                          DurationUnit::seconds, false);
    accept_duration_units(
        cmd.add_option("--degraded-limit", options.monitor.degraded_limit_s,
                       "longest loss of the monitor still judged DEGRADED rather than FAIL "
                       "(default 10s)")
            ->check(CLI::NonNegativeNumber),
        DurationUnit::seconds, false);
    cmd.add_option("--ladder", options.monitor.ladder,
                   "with --monitor: a storm at rising rates per second, a rung each, before the "
                   "cases: RATES (FC 03), KIND:RATES (KIND fc01, fc02, fc03, fc04, fc05, fc06, "
                   "fc07, fc08, fc0b, fc0c, fc0f, fc10, fc11, fc14, fc15, fc16, fc17, fc18, fc2b, "
                   "opens, slow-readers, half-open), or "
                   "requests:RATES (a ladder per function code served); repeatable")
        ->allow_extra_args(false);
    accept_duration_units(cmd.add_option("--ladder-step", options.monitor.ladder_step_s,
                                         "how long each rung of the ladder lasts (default 2s)")
                              ->check(CLI::PositiveNumber),
                          DurationUnit::seconds, false);
    cmd.add_option("--class", options.classes,
                   "try only these bad-input classes (comma-separated, or the option repeated)")
        ->delimiter(',');
    cmd.add_option("--skip-class", options.skip_classes,
                   "leave these bad-input classes out (comma-separated, or the option repeated)")
        ->delimiter(',');
    cmd.add_option("--device-pid", options.device_pid,
                   "process id of a device running on this machine: its memory is reported")
        ->check(CLI::PositiveNumber);
    add_tls_options(cmd, options.tls, "tester's (client)");
    cmd.add_option("--json", options.files.json,
                   "write the report as JSON to FILE (- for standard output)");
    cmd.add_option("--junit", options.files.junit,
                   "write the report as JUnit XML to FILE (- for standard output)");
    cmd.add_option("--pcap", options.files.pcap,
                   "write the run's frames as pcapng to FILE (a line's frames on "
                   "LINKTYPE_USER0); the last 32 MB or so of a longer run");
}

}  // namespace mblab::cli
