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

//! The end of every file command: a problem is printed (exit 1); a result is written to OUT and `summary(response)`
//! printed (exit 0).
template <class Summary>
int finish(const api::ApiResponse& response, const Parsed& parsed, Summary&& summary, ProblemStyle style = {}) {
    if (response.status >= 400) {
        std::cerr << "surfaced: " << parsed.input << ": ";
        if (const auto& problem = response.error) {
            if (style.field && problem->field && !problem->field->empty() &&
                !problem->detail.starts_with(*problem->field))
                std::cerr << *problem->field << ": ";
            std::cerr << problem->detail;
            if (style.line && problem->line)
                std::cerr << " (line " << *problem->line << ")";
            else if (style.offset && problem->offset)
                std::cerr << " (byte offset " << *problem->offset << ")";
            std::cerr << " [" << problem->code << "]";
        } else {
            std::cerr << "failed with status " << response.status;
        }
        std::cerr << "\n";
        return kExitFailed;
    }
    std::string error;
    if (!write_file(parsed.output, response.body, error)) {
        std::cerr << "surfaced: " << error << "\n";
        return kExitFailed;
    }
    summary(response);
    return kExitOk;
}

//! What repair did, on stderr ("repaired IN: welded=12; degenerate=3; ..."), when X-Repairs reports anything; the
//! output on stdout stays the operation's summary.
void print_repairs(const Parsed& parsed, const api::ApiResponse& response);

//! "wrote OUT: T triangles, V vertices (from F faces[, triangulated first])" of simplify and remesh.
void print_triangulated_result(const Parsed& parsed, const api::ApiResponse& response);

}  // namespace surfaced::cli
