// What the file commands print: the problem of a failed operation, the summary of a written result, the repairs.
#pragma once

#include <iostream>
#include <string>
#include <string_view>

#include "api/operation.h"
#include "server/cli/args.h"
#include "server/cli/files.h"

namespace surfaced::cli {

//! The value of response header `name`, "?" when absent.
std::string header(const api::ApiResponse& response, std::string_view name);

//! What a command's problem message locates: "surfaced: IN: [field: ]detail[ (line N)][ (byte offset N)] [code]".
struct ProblemStyle {
    bool field = false;  //!< the field path, when the detail does not start with it
    bool line = true;
    bool offset = true;  //!< (when there is no line)
};

//! A failed operation's problem on stderr: "surfaced: IN: [field: ]detail[ (line N)][ (byte offset N)] [code]"
//! (exit 1), or, when it is a 400 or 422 (but not a budget) about the value of an option given ("ratio must be in
//! (0, 1]"), the same mistake as an out-of-range value the command line checks itself: "surfaced: COMMAND --option:
//! detail" (exit 2).
int print_problem(const api::ApiResponse& response, const Parsed& parsed, ProblemStyle style);

//! The end of every file command: a problem is printed (exit 1 or 2: print_problem); a result is written to OUT and
//! `summary(response)` printed on parsed.report() (exit 0).
template <class Summary>
int finish(const api::ApiResponse& response, const Parsed& parsed, Summary&& summary, ProblemStyle style = {}) {
    if (response.status >= 400) return print_problem(response, parsed, style);
    std::string error;
    if (!write_file(parsed.output, response.body, error)) {
        std::cerr << "surfaced: " << error << "\n";
        return kExitFailed;
    }
    summary(response);
    return kExitOk;
}

//! What repair did, on stderr ("repaired IN: welded=12; degenerate=3; ..."), when X-Repairs reports anything (or
//! `always`); the output on stdout stays the operation's summary.
void print_repairs(const Parsed& parsed, const api::ApiResponse& response, bool always = false);

//! "wrote OUT: T triangles, V vertices (from F faces[, triangulated first])" of simplify and remesh.
void print_triangulated_result(const Parsed& parsed, const api::ApiResponse& response);

}  // namespace surfaced::cli
