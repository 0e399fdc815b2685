#pragma once

#include <chrono>
#include <functional>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "web/http_message.hpp"

// Which handler answers a request, as a table the server consults without a socket (the fuzz
// target and the tests use the same table serve does). A handler that throws is answered 500 and
// the process goes on: nothing a client sends may end it.
namespace mblab::web {

using HttpHandler = std::function<HttpReply(const HttpRequest&)>;
// The data of one server-sent event, from the query the stream was opened with.
using EventSource = std::function<std::string(const std::map<std::string, std::string>& query)>;

struct EventRoute {
    std::string path;
    EventSource source;
    std::chrono::milliseconds period{500};
};

class HttpRoutes {
  public:
    // GET (and HEAD) of exactly `path`.
    void get(std::string path, HttpHandler handler);
    // Every method at `prefix` and under `prefix`/.
    void under(std::string prefix, HttpHandler handler);
    // GET `path` opens a text/event-stream of source's data every `period`.
    void events(std::string path, EventSource source, std::chrono::milliseconds period);

    struct Outcome {
        HttpReply reply;
        const EventRoute* stream = nullptr;  // set: the answer is this stream, not `reply`
    };
    Outcome route(const HttpRequest& request) const;
    // One event of an open stream: "data: ...\n\n", or nullopt when the source failed.
    static std::optional<std::string> next_event(const EventRoute& route,
                                                 const std::map<std::string, std::string>& query);

  private:
    struct Route {
        std::string path;
        bool prefix = false;
        HttpHandler handler;
    };
    std::vector<Route> routes_;
    std::vector<EventRoute> events_;
};

HttpReply json_error(int status, const std::string& reason);

}  // namespace mblab::web
