#pragma once

#include <cassert>
#include <type_traits>
#include <utility>
#include <variant>

#include "protocol/exception_code.hpp"

namespace mblab::protocol {

// Why a decode failed: the field that is wrong, why, and the exception a server answers with.
// Strings are static so making an error never allocates.
struct DecodeError {
    ExceptionCode exception = ExceptionCode::IllegalDataValue;
    const char* field = "";
    const char* reason = "";
};

// A small std::expected stand-in (clang-14 with libstdc++ 12 has none).
template <class T, class E = DecodeError>
class [[nodiscard]] Result {
  public:
    Result(T value) : state_(std::in_place_index<0>, std::move(value)) {}  // NOLINT implicit
    Result(E error) : state_(std::in_place_index<1>, std::move(error)) {}  // NOLINT implicit

    bool ok() const { return state_.index() == 0; }
    explicit operator bool() const { return ok(); }

    T& value() & {
        assert(ok());
        return std::get<0>(state_);
    }
    const T& value() const& {
        assert(ok());
        return std::get<0>(state_);
    }
    T&& value() && {
        assert(ok());
        return std::get<0>(std::move(state_));
    }
    const E& error() const {
        assert(!ok());
        return std::get<1>(state_);
    }
    T* operator->() { return &value(); }
    const T* operator->() const { return &value(); }
    T& operator*() & { return value(); }
    const T& operator*() const& { return value(); }

  private:
    std::variant<T, E> state_;
};

}  // namespace mblab::protocol
