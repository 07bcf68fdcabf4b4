#pragma once
// Subcommands implemented outside main.cpp.
int cmd_bench(int argc, char** argv);
int cmd_plot(int argc, char** argv);
