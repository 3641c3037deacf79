// ratchet_planted: the ratchet command line with one physics term dropped through the
// test hook (world/test_hooks.hpp): the expansion velocity of an expanding wall at its
// contacts. regression/run --planted shows that the golden comparison catches it
// (regression/planted.json, docs/regression.md).
#include "cli_main.hpp"
#include "ratchet/world/test_hooks.hpp"

int main(int argc, char** argv) {
  ratchet::test_hooks().drop_wall_expansion = true;
  return ratchet_cli_main(argc, argv);
}
