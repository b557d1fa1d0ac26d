// The commands of `surfaced`, one function each: the arguments after the command's name in, the exit code out
// (kExitOk, kExitFailed; a UsageError thrown for bad usage).
#pragma once

#include "server/cli/args.h"

namespace surfaced::cli {

int serve(Args& args);
int healthcheck(Args& args);
int subdivide(Args& args);
int tessellate(Args& args);
int simplify(Args& args);
int remesh(Args& args);
int repair(Args& args);
int implicit(Args& args);
int pointcloud(Args& args);
int reconstruct(Args& args);
int curve(Args& args);
int surfaces(Args& args);
int query(Args& args);
int grid(Args& args);
int limit(Args& args);

}  // namespace surfaced::cli
