// The options every operation accepts, described once: name, type, range, default, units, a one-line description,
// the transports that carry it (query parameters of a file upload, members of a JSON body) and deprecated aliases.
// The query-string and JSON readers (option_reader.h) check names, types and ranges from these tables, so every
// operation words its errors the same way; tests/api/options_drift_test.cpp checks api/openapi.json against them;
// a front end (the CLI) can list an operation's options with operation_options().
//
// A table holds only data: each operation then moves the values it was given into its own Params struct.
#pragma once

#include <array>
#include <cstddef>
#include <optional>
#include <span>
#include <string_view>
#include <vector>

namespace surfaced::api::options {

enum class OptionType {
    Integer,  //!< a whole number (JSON: no fraction or exponent)
    Number,   //!< a finite number
    Bool,     //!< true or false (query: also 1 or 0)
    Enum,     //!< one of `values`
    List,     //!< a list of integers (query: comma-separated; JSON: an array); `min`/`max` bound each item
};

//! Where an option can be given. A query parameter goes with an uploaded file; a JSON member in a JSON body.
enum Transport : unsigned { kQuery = 1, kJson = 2, kBothTransports = kQuery | kJson };

struct Bound {
    double value = 0;
    bool exclusive = false;  //!< the value itself is out of range
};

struct OptionSpec {
    std::string_view name{};
    OptionType type = OptionType::Integer;
    std::optional<Bound> min{}, max{};
    //! `max` is the server's default limit (Limits), not a fixed range: the readers leave it to the operation, which
    //! checks the configured limit (422 budget_exceeded).
    bool max_is_limit = false;
    std::string_view default_json{};  //!< the default as JSON text ("1", "false", "\"glb\""); empty: none (unset)
    std::string_view units{};         //!< "degrees", "bits", "model units"; empty: none
    std::string_view description{};   //!< one line
    std::span<const std::string_view> values{};  //!< Enum: the accepted names
    unsigned transports = kBothTransports;
    //! In a JSON body the option is a member of this object ("output"); empty: a member of the body itself. Query
    //! parameters are never nested.
    std::string_view json_object{};
    std::span<const std::string_view> aliases{};  //!< deprecated names still accepted (for one release)

    bool on_query() const { return (transports & kQuery) != 0; }
    bool on_json() const { return (transports & kJson) != 0; }
};

struct OperationOptions {
    std::string_view operation{};           //!< "subdivide"
    std::string_view path{};                //!< the OpenAPI path, "/subdivide"
    std::string_view method{};              //!< "post"
    std::span<const OptionSpec> options{};  //!< the operation's own
    std::span<const OptionSpec> output{};   //!< the output options it shares with others (JSON: under "output")
    //! Members of the JSON body that are the input rather than options ("mesh", "creases", ...).
    std::span<const std::string_view> json_inputs{};
};

//! Every operation with a table (the ones whose readers use it).
std::span<const OperationOptions> operations();
//! The table of one operation by name ("subdivide", "simplify", ...); null when it has none.
const OperationOptions* operation_options(std::string_view operation);
//! The operation's own options, then its output options: the order of its OpenAPI parameters.
std::vector<const OptionSpec*> all_options(const OperationOptions& operation);
//! The option `name` (or one of its aliases) of `operation`; null when unknown.
const OptionSpec* find_option(const OperationOptions& operation, std::string_view name);

//! The names of an EnumName table (api/dto.h), so a spec's `values` and the parser share one list.
template <class Entry, std::size_t N>
constexpr std::array<std::string_view, N> names_of(const Entry (&table)[N]) {
    std::array<std::string_view, N> out{};
    for (std::size_t i = 0; i < N; ++i) out[i] = table[i].name;
    return out;
}

}  // namespace surfaced::api::options
