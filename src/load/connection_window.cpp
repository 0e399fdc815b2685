#include <algorithm>
#include <cstring>

#include "load/connection.hpp"
#include "protocol/adu_writer.hpp"
#include "protocol/mbap_header.hpp"

// The window of requests of a LoadConnection: which exchange goes next, the slots its
// transaction ids name, the requests put in out_, and each answer matched to its request and
// judged, or its request timed out. connection.cpp holds the connection and its bytes.
namespace mblab::load {

namespace {

using std::chrono::duration_cast;
using std::chrono::microseconds;

constexpr std::chrono::milliseconds kMaxSendDebt{50};

}  // namespace

bool LoadConnection::next_exchange(std::uint32_t& out) {
    if (role_ == Role::Traffic) {
        out = next_mix_exchange(context_.plan, prng_);
        return true;
    }
    return next_test_exchange(context_.plan, tally_, test_cursor_, out);
}

LoadConnection::Slot& LoadConnection::take_slot() {
    const std::uint16_t index = free_slots_.back();
    free_slots_.pop_back();
    Slot& slot = slots_[index];
    ++slot.generation;
    const unsigned generation_bits = 16 - slot_bits_;
    const auto generation = static_cast<std::uint16_t>(
        generation_bits >= 16 ? slot.generation : slot.generation & ((1U << generation_bits) - 1));
    slot.tid = static_cast<std::uint16_t>((generation << slot_bits_) | index);
    slot.active = true;
    ++outstanding_;
    return slot;
}

void LoadConnection::release(Slot& slot) {
    slot.active = false;
    --outstanding_;
    free_slots_.push_back(static_cast<std::uint16_t>(&slot - slots_.data()));
}

LoadConnection::Slot* LoadConnection::find_slot(std::uint16_t tid) {
    const std::size_t index = tid & ((1U << slot_bits_) - 1);
    if (index >= slots_.size()) return nullptr;
    Slot& slot = slots_[index];
    return slot.active && slot.tid == tid ? &slot : nullptr;
}

LoadConnection::Slot* LoadConnection::oldest_slot() {
    Slot* oldest = nullptr;
    for (auto& slot : slots_) {
        if (slot.active && (oldest == nullptr || slot.sent_at < oldest->sent_at)) oldest = &slot;
    }
    return oldest;
}

void LoadConnection::fill(LoadClock::time_point now) {
    if (!context_.running || state_ != State::Open) return;
    const auto interval = context_.send_interval;
    const auto timeout = context_.plan.settings.timeout;
    while (outstanding_ < window_) {
        if (interval.count() > 0) {
            if (now < next_send_) break;
            // Sends wait for the next tick (a millisecond or more on a busy machine), so some
            // lag is made up later; but after a real stall the debt is forgiven rather than
            // paid back as a burst.
            const auto debt = std::max<std::chrono::nanoseconds>(
                interval * static_cast<long>(window_), kMaxSendDebt);
            if (next_send_ + debt < now) next_send_ = now - debt;
            next_send_ += interval;
        }
        std::uint32_t index = 0;
        if (!next_exchange(index)) break;
        const auto& request = context_.plan.exchanges[index].request;
        if (out_end_ + request.size() > out_.size()) break;
        Slot& slot = take_slot();
        slot.exchange = index;
        slot.sent_at = now;
        earliest_deadline_ = std::min(earliest_deadline_, now + timeout);
        std::memcpy(out_.data() + out_end_, request.data(), request.size());
        protocol::put_mbap_transaction_id({out_.data() + out_end_, request.size()}, slot.tid);
        out_end_ += request.size();
        tally_.sent.add();
        tally_.exchange(index).sent.add();
    }
    flush(now);
}

void LoadConnection::answer(std::span<const std::uint8_t> frame, LoadClock::time_point now) {
    const std::uint16_t tid = protocol::read_mbap_header(frame).transaction_id;
    Slot* slot = find_slot(tid);
    bool tid_matches = slot != nullptr;
    if (slot == nullptr) {
        const std::size_t index = tid & ((1U << slot_bits_) - 1);
        if (index < slots_.size() && slots_[index].has_expired &&
            slots_[index].expired_tid == tid) {
            slots_[index].has_expired = false;
            tally_.late.add();
            return;
        }
        // Modbus/TCP servers answer in order: take it as the answer to the oldest request.
        slot = oldest_slot();
    }
    tally_.answered.add();
    if (slot == nullptr) {
        fail(FailureKind::WrongAnswer, nullptr, {client::ReceiveStatus::Frame, frame, {}}, now,
             "an answer that no request asked for");
        return;
    }
    tally_.latency.record(
        static_cast<std::uint64_t>(duration_cast<microseconds>(now - slot->sent_at).count()));
    std::optional<FailureKind> failure =
        tid_matches
            ? judge_load_answer(context_.plan, tally_, role_ == Role::Tests, slot->exchange, frame)
            : FailureKind::WrongAnswer;
    if (failure) fail(*failure, slot, {client::ReceiveStatus::Frame, frame, {}}, now);
    release(*slot);
}

void LoadConnection::expire(LoadClock::time_point now) {
    const auto timeout = context_.plan.settings.timeout;
    earliest_deadline_ = LoadClock::time_point::max();
    for (auto& slot : slots_) {
        if (!slot.active) continue;
        const auto deadline = slot.sent_at + timeout;
        if (deadline > now) {
            earliest_deadline_ = std::min(earliest_deadline_, deadline);
            continue;
        }
        fail(FailureKind::Timeout, &slot, {client::ReceiveStatus::Timeout, held(), {}}, now);
        slot.expired_tid = slot.tid;
        slot.has_expired = true;
        release(slot);
    }
}

void LoadConnection::fail(FailureKind kind, const Slot* slot, const LoadSeen& seen,
                          LoadClock::time_point now, std::string_view reason) {
    if (slot == nullptr) {
        count_failure(tally_, context_.plan, context_.start, kind, nullptr, seen, now, reason);
        return;
    }
    const LoadSent sent{slot->exchange, slot->tid};
    count_failure(tally_, context_.plan, context_.start, kind, &sent, seen, now, reason);
}

}  // namespace mblab::load
