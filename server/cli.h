// The `surfaced` command line: `serve` runs the HTTP service, `subdivide` runs the same operation on files.
#pragma once

namespace surfaced::cli {

//! Exit codes: 0 success, 1 the operation failed (bad mesh, budget, I/O), 2 bad command-line usage.
int run(int argc, char** argv);

}  // namespace surfaced::cli
