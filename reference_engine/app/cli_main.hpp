// The ratchet command line as a function, so that the test-only planted-regression
// program (regression/planted_main.cpp) runs exactly the same code after setting a hook.
#pragma once

int ratchet_cli_main(int argc, char** argv);
