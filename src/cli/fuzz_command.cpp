#include <fmt/core.h>
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <atomic>
#include <csignal>
#include <cstdlib>
#include <fstream>
#include <memory>
#include <sstream>
#include <string>
#include <string_view>
#include <vector>

#include "cli/client_options.hpp"
#include "cli/commands.hpp"
#include "cli/fuzz_inputs.hpp"
#include "cli/fuzz_monitor.hpp"
#include "cli/fuzz_options.hpp"
#include "cli/fuzz_output.hpp"
#include "cli/report_files.hpp"
#include "cli/stop_signals.hpp"
#include "cli/tls_options.hpp"
#include "client/raw_link.hpp"
#include "client/target.hpp"
#include "conformance/capture.hpp"
#include "conformance/dut.hpp"
#include "conformance/provenance.hpp"
#include "conformance/reports.hpp"
#include "conformance/session.hpp"
#include "robustness/case_generator.hpp"
#include "robustness/class_choice.hpp"
#include "robustness/fuzz_progress.hpp"
#include "robustness/fuzz_report.hpp"
#include "robustness/fuzz_run.hpp"
#include "robustness/iec62443_report.hpp"
#include "robustness/learn.hpp"
#include "robustness/pcap_reader.hpp"
#include "robustness/probe_finding.hpp"
#include "robustness/recon.hpp"
#include "robustness/reproducer.hpp"
#include "robustness/session_ask.hpp"
#include "transport/serial_port.hpp"

// `mblab fuzz TARGET`: the robustness tester (docs/robustness.md).
namespace mblab::cli {

namespace {

namespace rb = mblab::robustness;
namespace conf = mblab::conformance;

// What --pcap keeps of a run, in bytes of memory: a run's capture is otherwise unbounded.
constexpr std::size_t kPcapBound = std::size_t{32} << 20;

int usage_error(const std::string& message) {
    fmt::print(stderr, "mblab fuzz: {}\n", message);
    return kExitUsage;
}

conf::Provenance provenance_of(const FuzzCommandOptions& options,
                               std::chrono::system_clock::time_point started) {
    conf::Provenance provenance;
    if (options.invocation != nullptr) {
        provenance.version = options.invocation->version;
        provenance.commit = options.invocation->commit;
        provenance.command_line = options.invocation->argv;
    }
    provenance.started = conf::iso8601_utc(started);
    provenance.finished = conf::iso8601_utc(std::chrono::system_clock::now());
    provenance.declared_by = !options.dut_file.empty() ? options.dut_file
                             : !options.learn.empty()  ? options.learn
                                                       : "reconnaissance";
    provenance.device.reason = "not asked: the robustness tester does not read identification";
    return provenance;
}

int run_fuzz(const FuzzCommandOptions& options) {
    const auto started = std::chrono::system_clock::now();
    ReportFiles files;
    std::string unwritable;
    if (!files.check("--json", options.files.json, unwritable) ||
        !files.check("--junit", options.files.junit, unwritable)) {
        return usage_error(unwritable);
    }
    // A report on standard output has it to itself.
    std::FILE* const console = files.uses_standard_output() ? stderr : stdout;
    auto target = client::parse_target(options.target);
    if (!target) return usage_error(target.error());
    if (target->secure) {
        if (auto failed = client::attach_tls(*target, options.tls); !failed.empty())
            return usage_error(failed);
    }
    const auto framing = client::framing_of(*target);
    const bool line = framing != client::Framing::Mbap;
    if (line && !options.learn.empty())
        return usage_error(
            fmt::format("--learn: captures are of Modbus/TCP only, not {}", target->name));
    if (options.cases == 0 && options.duration <= 0 && options.replay.empty())
        return usage_error("no budget: give --cases N or --duration D (it is pointed at devices)");
    const auto chosen = rb::choose_classes(options.classes, options.skip_classes);
    if (!chosen) return usage_error(chosen.error());
    if (auto wrong = FuzzMonitor::check(options.monitor); !wrong.empty()) return usage_error(wrong);
    ReportDir report_dir(options.report_dir);
    rb::ReconOptions recon_options;
    recon_options.unit = static_cast<std::uint8_t>(options.unit);
    recon_options.allow_writes = options.allow_writes;
    conf::Dut declared;
    if (!options.dut_file.empty()) {
        auto dut = conf::load_dut_file(options.dut_file);
        if (!dut) return usage_error(dut.error());
        declared = *dut;
        recon_options.unit = dut->unit;
        recon_options.max_read = dut->max_read;
    }
    // Learned before connecting: a capture that teaches nothing is the user's to fix first.
    std::optional<rb::Recon> learned;
    if (!options.learn.empty()) {
        std::string bytes;
        if (!read_file(options.learn, bytes))
            return usage_error(fmt::format("{}: cannot read the capture", options.learn));
        const auto capture = rb::read_pcap(
            std::span(reinterpret_cast<const std::uint8_t*>(bytes.data()), bytes.size()));
        if (!capture) return usage_error(fmt::format("{}: {}", options.learn, capture.error()));
        auto recon = rb::learn_recon(*capture, target->tcp->port, options.learn);
        if (!recon) return usage_error(recon.error());
        learned = std::move(*recon);
        if (options.unit_given) learned->unit = recon_options.unit;
        if (!options.dut_file.empty()) {
            learned->unit = recon_options.unit;
            learned->max_read = *recon_options.max_read;
            learned->source += fmt::format("; unit and max_read declared by {}", options.dut_file);
        }
    }
    if (line && recon_options.unit == 0)
        return usage_error(
            "unit 0 is broadcast, never answered on a serial line: give the "
            "device's address (--unit)");
    rb::WritePolicy policy{options.allow_writes, std::nullopt};
    if (!options.writable.empty()) {
        policy.writable = parse_writable(options.writable);
        if (!policy.writable) {
            return usage_error(
                fmt::format("--writable '{}' is not START:COUNT of holding registers (e.g. 100:10)",
                            options.writable));
        }
    }
    std::optional<rb::DeviceMemory> memory;
    if (options.device_pid != 0) {
        const auto now = process_memory(options.device_pid);
        if (!now)
            return usage_error(fmt::format("--device-pid {}: no such process on this machine",
                                           options.device_pid));
        memory = rb::DeviceMemory{options.device_pid, now->first, 0, 0};
    }
    std::signal(SIGPIPE, SIG_IGN);
    const auto timeout = std::chrono::milliseconds(options.timeout_ms);
    // The largest many-connections case holds two thousand connections where descriptors allow.
    rb::ResourceLimits limits;
    const std::size_t descriptors = raise_descriptor_limit();
    limits.connections = std::min<std::size_t>(2000, descriptors > 300 ? descriptors - 200 : 100);
    limits.half_open = client::RawLink::can_vanish();

    // Reconnaissance over one connection, one request at a time.
    conf::Dut dut;
    dut.unit = recon_options.unit;
    conf::EngineOptions engine;
    engine.timeout = timeout;
    engine.connect_timeout = timeout;
    // Without --pcap nothing of the traffic is kept: against a device that floods its answers
    // that was every byte of the run. With it, the run's last kPcapBound bytes or so are kept.
    conf::Capture capture(kPcapBound);
    client::LinkObserver* observer = options.files.pcap.empty() ? nullptr : &capture;
    conf::Session session(*target, dut, engine, observer);
    client::LinkError error;
    if (!session.connect(error))
        return usage_error(fmt::format("{}: {}", target->name, error.message));
    const rb::Ask ask = rb::session_ask(session, timeout);
    rb::Recon recon;
    if (learned) {
        recon = std::move(*learned);
    } else {
        if (auto failed = rb::reconnoitre(ask, recon_options, recon))
            return usage_error(fmt::format("{}: {}", target->name, *failed));
        if (!options.dut_file.empty()) recon.source = options.dut_file;
    }
    session.close();
    // Where the FC 14 and FC 18 storms read first, before the places they probe.
    recon.file_number = declared.file_number;
    recon.fifo_address = declared.fifo_address;
    fmt::print(console, "mblab fuzz {}\n{}", target->name, rb::recon_text(recon));
    std::fflush(console);
    if (recon.killed_by && options.replay.empty()) {
        return write_fuzz_outputs(rb::probe_finding(recon, target->name, options.seed, framing),
                                  *target, FuzzOutputs{console, options.files}, report_dir, capture,
                                  provenance_of(options, started));
    }

    auto monitor = FuzzMonitor::make(options.monitor, *target, recon, policy, timeout);
    if (!monitor) return usage_error(monitor.error());

    rb::FuzzOptions fuzz;
    fuzz.target = *target;
    fuzz.seed = options.seed;
    fuzz.rate = options.rate;
    fuzz.check_every = options.check_every;
    fuzz.timeout = timeout;
    const auto times = transport::rtu_char_times(
        target->serial && target->serial->kind != transport::SerialUrl::Kind::RtuOverTcp
            ? target->serial->line.baud
            : 19200);
    // The line-gap class pauses between t1.5 and t3.5 where milliseconds allow; the oracle
    // waits for more than t3.5 of silence before it asks.
    const auto gap =
        std::max(std::chrono::milliseconds(1),
                 std::chrono::ceil<std::chrono::milliseconds>((times.t15 + times.t35) / 2));
    fuzz.quiet = std::max(std::chrono::milliseconds(5),
                          std::chrono::ceil<std::chrono::milliseconds>(times.t35) * 2);
    if (options.cases > 0) fuzz.cases = options.cases;
    if (options.duration > 0)
        fuzz.duration = std::chrono::milliseconds(static_cast<long>(options.duration * 1000));
    if (!options.restart.empty())
        fuzz.restart = [command = options.restart] { return run_restart(command); };
    fuzz.keep_going = options.keep_going;
    fuzz.timeline = *monitor != nullptr;
    rb::FuzzRunner runner(fuzz, recon, observer);

    if (!options.replay.empty()) {
        std::string text;
        if (!read_file(options.replay, text))
            return usage_error(fmt::format("{}: cannot read the reproducer", options.replay));
        auto steps = rb::parse_reproducer(text);
        if (!steps) return usage_error(fmt::format("{}: {}", options.replay, steps.error()));
        const auto liveness = runner.replay(*steps);
        if (liveness.alive) {
            fmt::print(console,
                       "replayed {} frame(s): the device still serves (checked in {} ms)\n",
                       steps->size(), liveness.waited.count());
            return kExitOk;
        }
        fmt::print(console, "replayed {} frame(s): the device {} (waited {} ms)\n", steps->size(),
                   liveness.reason, liveness.waited.count());
        return kExitFailed;
    }

    StopSignals::catch_them();
    const bool live = ::isatty(STDERR_FILENO) != 0;
    rb::CaseGenerator generator(recon, policy, options.seed, framing, gap, limits);
    generator.choose(*chosen);
    rb::ProgressBudget budget{fuzz.cases, fuzz.duration};
    // Without mutations the run ends with the fixed cases.
    if (!generator.chosen(rb::BadInput::Mutation))
        budget.cases =
            std::min(budget.cases.value_or(generator.fixed_cases()), generator.fixed_cases());
    if (*monitor) {
        (*monitor)->baseline();
        (*monitor)->ladder(live);
        (*monitor)->malformed_begin();
    }
    const auto run_start = std::chrono::steady_clock::now();
    auto result = runner.run(
        generator,
        [&](const rb::FuzzResult& so_far, const rb::FuzzCase& c) {
            if (!live) return;
            const auto elapsed = std::chrono::duration_cast<std::chrono::milliseconds>(
                std::chrono::steady_clock::now() - run_start);
            const auto line =
                rb::progress_text(so_far.cases, budget, elapsed,
                                  fmt::format("{}: {}", rb::class_name(c.kind), c.name));
            fmt::print(stderr, "\r\033[K{}", line);
            std::fflush(stderr);
        },
        [] { return StopSignals::requested(); });
    if (live) fmt::print(stderr, "\r\033[K");
    if (memory) {
        if (const auto now = process_memory(memory->pid)) {
            memory->end_kb = now->first;
            memory->peak_kb = now->second;
            result.memory = memory;
        }
    }
    FuzzOutputs outputs{console, options.files};
    if (*monitor) {
        (*monitor)->recover();
        const auto judged = (*monitor)->judge(result);
        outputs.monitor_text = (*monitor)->text(judged);
        outputs.monitor = (*monitor)->json(judged);
        outputs.monitor_html = (*monitor)->html(result, judged);
        outputs.monitor_junit = (*monitor)->junit(judged);
        outputs.monitor_passed = judged.verdict == rb::MonitorVerdict::Pass;
    }
    return write_fuzz_outputs(result, *target, outputs, report_dir, capture,
                              provenance_of(options, started));
}

// What `mblab --help` says of the command.
constexpr std::string_view kSummary =
    "Robustness test: bad input of every class docs/robustness.md lists, then random "
    "mutations, "
    "with a liveness check after each case; a finding is minimised to a reproducer";
constexpr std::string_view kHelp = R"(
Exit status: 0 no finding, 1 a finding (the device stopped serving), 2 usage error,
a file that cannot be read or written, or a target unreachable at start.
Example: mblab fuzz tcp://127.0.0.1:1502 --cases 300 --junit fuzz.xml
Example: mblab fuzz 'rtu:///dev/ttyUSB0?baud=19200' --unit 17 --cases 300
Example: mblab fuzz tcp://10.0.0.5 --keep-going --restart CMD --skip-class many-connections)";

}  // namespace

void add_fuzz_command(CLI::App& app, CommandRunner& runner, const Invocation& invocation) {
    // Named variables, not a structured binding: the callback below captures them, which
    // clang 14 refuses for a binding.
    const auto added = add_command<FuzzCommandOptions>(app, runner, "fuzz", std::string(kSummary),
                                                       help_text(kHelp), run_fuzz);
    CLI::App* cmd = added.first;
    auto options = added.second;
    options->invocation = &invocation;
    add_fuzz_options(*cmd, *options);
    cmd->callback([options, cmd, &runner] {
        options->unit_given = cmd->count("--unit") > 0;
        runner = [options] { return run_fuzz(*options); };
    });
}

}  // namespace mblab::cli
