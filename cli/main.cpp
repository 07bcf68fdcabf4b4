// salsa: the headless front-end. The commands are in the salsa_cli library (entry.cpp).
#include "embed.hpp"

int main(int argc, char** argv) { return salsa::cli::run_command(argc, argv); }
