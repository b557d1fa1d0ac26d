// RequestLog: records every answered request in the metrics and, when the access log is on, as one JSON line on
// stdout or stderr; likewise the connections the server turns away because it is overloaded.
#pragma once

#include <mutex>
#include <string>

#include "server/http_exchange.h"
#include "server/http_server.h"

namespace surfaced::server {

class Metrics;

class RequestLog {
public:
    RequestLog(ServerConfig::AccessLog where, Metrics& metrics);

    //! The request `record` describes is done; nothing is recorded when it was not answered (status 0).
    void finished(const RequestRecord& record);
    //! A connection is turned away (every worker busy, the queue full): counted before it is answered 503 or closed.
    void shed();
    //! The shedding path answered a connection 503 with request id `id`.
    void shed_answered(const std::string& id);

private:
    void write_line(const std::string& line);

    const ServerConfig::AccessLog where_;
    Metrics& metrics_;
    std::mutex mutex_;
};

}  // namespace surfaced::server
