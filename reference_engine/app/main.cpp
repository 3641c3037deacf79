// The ratchet program (docs/cli.md).
#include "cli_main.hpp"

int main(int argc, char** argv) { return ratchet_cli_main(argc, argv); }
