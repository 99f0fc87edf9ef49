// Subcommands of the `cubeao` CLI (DESIGN.md §5). Each add* function registers one subcommand on
// the app; its callback throws cubeao::Error (exit 1) or cubeao::UsageError (exit 2) on failure and,
// with --json, prints exactly one JSON object as the last line of stdout through printJson().
#pragma once

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

namespace cubeao::cli {

void addInfo(CLI::App& app);
void addReference(CLI::App& app);
void addCompare(CLI::App& app);
void addPlace(CLI::App& app);
void addBake(CLI::App& app);
void addMerge(CLI::App& app);
void addExport(CLI::App& app);
void addBench(CLI::App& app);
void addRender(CLI::App& app);
void addReport(CLI::App& app);
// `bench` subcommands in files of their own, registered by addBench on the `bench` subcommand.
void addBenchDepth(CLI::App& bench);
void addBenchCache(CLI::App& bench);
void addBenchRender(CLI::App& bench);

// Prints `j` compactly on one line to stdout (the last line a --json command prints). An object gets
// `peak_rss_mb` (peakRssMib, when it has none yet), so every stage of a pipeline reports its memory.
void printJson(const nlohmann::json& j);
// Peak resident set of this process so far (getrusage), MiB.
double peakRssMib();

}  // namespace cubeao::cli
