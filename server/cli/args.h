// The command line's vocabulary: usage errors and exit codes, the argument reader, the options of the file commands
// (an option, its check, the operation option it sets) and the parser they share.
#pragma once

#include <charconv>
#include <cstddef>
#include <functional>
#include <iostream>
#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "api/dto.h"
#include "api/options/option_spec.h"

namespace surfaced::cli {

//! The exit codes of every command (listed in `surfaced --help`): the operation succeeded; the operation failed (its
//! problem: the input's geometry, a budget, a file that cannot be read or written); the command line is wrong (an
//! unknown command, option or value, a missing or out-of-range argument), whichever command it is.
constexpr int kExitOk = 0;
constexpr int kExitFailed = 1;
constexpr int kExitUsage = 2;

struct UsageError {
    std::string message;
};

//! Splits argv into options and positionals; accepts "--name value" and "--name=value".
class Args {
public:
    Args(int argc, char** argv, int first) {
        for (int i = first; i < argc; ++i) args_.emplace_back(argv[i]);
    }
    bool done() const { return pos_ >= args_.size(); }
    std::string next() { return args_[pos_++]; }
    //! The value of option `name` (inline after '=' or the next argument).
    std::string value(std::string_view name, std::optional<std::string>& inline_value) {
        if (inline_value) return *std::exchange(inline_value, std::nullopt);
        if (done()) throw UsageError{std::string(name) + " needs a value"};
        return next();
    }

private:
    std::vector<std::string> args_;
    std::size_t pos_ = 0;
};

long long parse_number(std::string_view name, const std::string& text, long long min, long long max);

//! The word of `known` closest to `typed` by edit distance (insertions, deletions, substitutions, swaps of two
//! neighbours), when it is close enough to be a typo of it; nullopt otherwise.
std::optional<std::string_view> closest_match(std::string_view typed, const std::vector<std::string_view>& known);

//! `option`'s error for `text` not among `allowed`: "--scheme: unknown value "catmul-clark" (did you mean
//! "catmull-clark"? allowed: "catmull-clark", "loop")".
UsageError unknown_value(std::string_view option, const std::string& text,
                         const std::vector<std::string_view>& allowed);

//! The error for an unknown option `arg` of `command` with its `known` options: "subdivide: unknown option
//! "--levle" (did you mean --levels?)".
UsageError unknown_option(std::string_view command, const std::string& arg, const std::vector<std::string_view>& known);

//! The option loop of every command: splits "--name=value" and hands each argument to `handle(arg, inline_value)`,
//! which takes the value it needs (Args::value); a value left over is an error ("--normals=yes"). `handle` returns
//! false when the command is done (it printed its help); so does this.
template <class Handle>
bool for_each_argument(Args& args, Handle&& handle) {
    while (!args.done()) {
        std::string arg = args.next();
        std::optional<std::string> inline_value;
        if (const auto eq = arg.find('='); arg.starts_with("--") && eq != std::string::npos) {
            inline_value = arg.substr(eq + 1);
            arg.resize(eq);
        }
        if (!handle(arg, inline_value)) return false;
        if (inline_value) throw UsageError{arg + " takes no value"};
    }
    return true;
}

//! Checks an option's value and returns the text to pass on, or throws a UsageError naming the option.
using CheckValue = std::function<std::string(std::string_view option, const std::string& text)>;

//! A number option as text, checked to parse (the operation checks its range).
std::string checked_real(std::string_view name, const std::string& text);

CheckValue integer(long long min, long long max);
CheckValue real();
//! One of `allowed` (for choices that have no table in api/dto.h).
CheckValue one_of_names(std::vector<std::string_view> allowed);

//! An option of a command: "--name VALUE" (checked by `check`), or a switch "--name" (no `check`). The options of
//! an operation's table are generated from it (table_options.h); the others are written by hand.
struct Option {
    std::string name{};  //!< "--levels"
    //! The operation option it sets (its name in the table: the query parameter or JSON member it becomes); empty:
    //! the command reads it itself.
    std::string param{};
    CheckValue check{};
    std::string switch_value = "true";  //!< what a switch sets `param` to
    //! The table row of `param`, for generated options (their help comes from it).
    const api::options::OptionSpec* spec = nullptr;
    //! A deprecated spelling: the flag to use instead ("--compression none"); listed apart in the help.
    std::string replaced_by{};
    //! Hand-written help: "--bounds X0,Y0,Z0,X1,Y1,Z1" and its description (generated options have none).
    std::string synopsis{}, description{};
};

//! A switch: "--name" (no value) gives `param`, if any, the value `value`.
Option flag(std::string name, std::string param = "", std::string value = "true");

//! The arguments of `COMMAND IN -o OUT [options]`: the options given, each with its last (checked) value.
struct Parsed {
    std::string command;
    std::string input, output;
    //! The options the command reads itself, by flag ("--bounds"), with their values ("" for switches).
    std::map<std::string, std::string, std::less<>> given;
    //! The operation's options given, by their names in its table, with the values to send ("true" for a switch).
    std::map<std::string, std::string, std::less<>> params;
    //! The flag given for each request field ("format", "levels", "cell_size"): a 400 problem about one of these is a
    //! bad value on the command line.
    std::map<std::string, std::string, std::less<>> option_by_field;

    //! The given option whose value a problem's `field` names ("ratio", "locked_vertices[3]", "output.normals"),
    //! if any.
    std::optional<std::string> option_for_field(std::string_view field) const;

    bool has(std::string_view name) const { return given.find(name) != given.end(); }
    //! The value given to the operation's option `name` (its table name), if any.
    std::optional<std::string> param(std::string_view name) const {
        const auto it = params.find(name);
        return it == params.end() ? std::nullopt : std::optional<std::string>(it->second);
    }
    //! IN "-": standard input; OUT "-": standard output, and then the reports go to stderr.
    bool from_stdin() const { return input == "-"; }
    bool to_stdout() const { return output == "-"; }
    //! Where the summary and the other human-readable reports go: stdout, unless it carries the output file.
    std::ostream& report() const { return to_stdout() ? std::cerr : std::cout; }
    //! IN and OUT as the messages name them.
    std::string input_label() const { return from_stdin() ? "standard input" : input; }
    std::string output_label() const { return to_stdout() ? "standard output" : output; }
    //! The value of an option that `has` been given.
    const std::string& value(std::string_view name) const { return given.find(name)->second; }
};

//! Parses the arguments of a file command against its `options`, with the wording every command shares: -h/--help
//! prints `help` (nullopt: the command is done), -o/--output, --format (the output format; see output_format()),
//! unknown options, one IN (`input_name` when missing), OUT required. IN and OUT may be "-". A value that fails its
//! check is a UsageError naming the command and the option.
std::optional<Parsed> parse_file_command(Args& args, const std::string& command, std::string_view help,
                                         const std::vector<Option>& options,
                                         const std::string& input_name = "input file");

}  // namespace surfaced::cli
