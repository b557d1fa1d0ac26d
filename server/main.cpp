// `surfaced`: everything lives in cli/ (entry point cli.h) so that main stays a one-liner.
#include "server/cli.h"

int main(int argc, char** argv) { return surfaced::cli::run(argc, argv); }
