// The `surfaced` command line: `serve` runs the HTTP service, the file commands (`subdivide`, `simplify`, ...) run the
// same operations on files, in process. The commands live in server/cli/.
#pragma once

namespace surfaced::cli {

//! Exit codes: 0 success, 1 the operation failed (bad mesh, budget, I/O), 2 bad command-line usage (including an
//! option value the operation refuses as out of range).
int run(int argc, char** argv);

}  // namespace surfaced::cli
