#include "robustness/case_links.hpp"

#include <algorithm>

namespace mblab::robustness {

namespace {

// Every connection of a case is a link of its own; the check asks on a fresh one.
class ConnectionLinks final : public CaseLinks {
  public:
    using CaseLinks::CaseLinks;

    void after_frame(std::size_t /*connection*/) override {}
    void end_case(bool hold) override {
        // Answers are read, not judged: what a device answers to garbage is conformance's.
        bool first = true;
        for (std::size_t i = 0; i < links_.size(); ++i) {
            auto& link = links_[i];
            if (!link || !link->is_open() || unread_[i]) continue;
            link->receive_any(first ? times_.settle : std::chrono::milliseconds(1));
            first = false;
        }
        if (!hold) close_case_links();
    }
    void end_check() override { close_case_links(); }
    std::size_t numbers_taken(std::size_t connections) const override { return connections; }

    client::Link* ask_on(client::LinkError& error) override {
        close(fresh_);
        return dial_into(fresh_, error);
    }
    void done_asking() override { close(fresh_); }
    void open_bystander() override {
        client::LinkError error;
        dial_into(bystander_, error);
    }
    int asks() const override { return 1; }
    std::string_view asked_on() const override { return "a fresh connection"; }
    std::string_view unreachable() const override { return "refuses connections"; }

  private:
    std::size_t route(std::size_t connection) const override { return connection; }
};

// One link carries the run; a frame's answer is read until the line is quiet before the next.
class LineLinks final : public CaseLinks {
  public:
    using CaseLinks::CaseLinks;

    void after_frame(std::size_t /*connection*/) override {
        drain(std::max(times_.settle, times_.quiet));
    }
    void end_case(bool /*hold*/) override {}
    void end_check() override {}
    // Every case goes on the one link: a reproducer names no other.
    std::size_t numbers_taken(std::size_t /*connections*/) const override { return 0; }

    // Late answers to the case are read and dropped, then the line is left quiet. A connection
    // (RTU over TCP) that the device closed on bad input is opened again: its right, as over
    // Modbus/TCP.
    client::Link* ask_on(client::LinkError& error) override {
        drain(times_.quiet);
        auto* link = open(0, error);
        if (link != nullptr) clock_.sleep(times_.quiet);
        return link;
    }
    void done_asking() override {}
    void open_bystander() override {}
    int asks() const override { return 2; }
    std::string_view asked_on() const override { return "the link"; }
    std::string_view unreachable() const override { return "cannot be reached"; }

  private:
    std::size_t route(std::size_t /*connection*/) const override { return 0; }

    // Bounded: a device that talks without end is the check's to judge.
    void drain(std::chrono::milliseconds first) {
        for (int i = 0; i < 64; ++i) {
            auto* link = carry(0, false);
            if (link == nullptr) return;
            const auto got = link->receive_any(i == 0 ? first : times_.quiet);
            if (got.status == client::ReceiveStatus::Closed) {
                drop(0);
                return;
            }
            if (got.status != client::ReceiveStatus::Frame && got.bytes.empty()) return;
        }
    }
};

}  // namespace

CaseLinks::CaseLinks(Dial dial, LinkTimes times, RunClock clock)
    : dial_(std::move(dial)), times_(times), clock_(std::move(clock)) {}

CaseLinks::~CaseLinks() = default;

client::Link* CaseLinks::carry(std::size_t connection, bool open_it) {
    const std::size_t at = route(connection);
    if (at < links_.size() && links_[at] && links_[at]->is_open()) return links_[at].get();
    if (!open_it) return nullptr;
    client::LinkError error;
    return open(at, error);
}

client::Link* CaseLinks::open(std::size_t at, client::LinkError& error) {
    if (links_.size() <= at) {
        links_.resize(at + 1);
        unread_.resize(at + 1, false);
    }
    auto& link = links_[at];
    if (link && link->is_open()) return link.get();
    return dial_into(link, error);
}

client::Link* CaseLinks::dial_into(std::unique_ptr<client::Link>& slot, client::LinkError& error) {
    auto opened = dial_();
    if (!opened) {
        error = opened.error();
        return nullptr;
    }
    slot = std::move(opened.value());
    return slot.get();
}

void CaseLinks::drop(std::size_t connection) {
    const std::size_t at = route(connection);
    if (at < links_.size()) links_[at].reset();
}

void CaseLinks::leave_unread(std::size_t connection) {
    const std::size_t at = route(connection);
    if (at < unread_.size()) unread_[at] = true;
}

void CaseLinks::close(std::unique_ptr<client::Link>& link) {
    if (link) link->close();
    link.reset();
}

void CaseLinks::close_case_links() {
    for (auto& link : links_)
        close(link);
    links_.clear();
    unread_.clear();
}

void CaseLinks::close_bystander() {
    close(bystander_);
}

void CaseLinks::close_all() {
    close_case_links();
    close(fresh_);
    close(bystander_);
}

std::unique_ptr<CaseLinks> make_case_links(client::Framing framing, Dial dial, LinkTimes times,
                                           RunClock clock) {
    if (framing == client::Framing::Mbap)
        return std::make_unique<ConnectionLinks>(std::move(dial), times, std::move(clock));
    return std::make_unique<LineLinks>(std::move(dial), times, std::move(clock));
}

}  // namespace mblab::robustness
