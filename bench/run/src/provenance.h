#pragma once
// Internal: what produced a stage of the run, so that --resume reuses only what this run would
// have made itself. A provenance is named parts (the program, the data's content, the SNRs, the
// training options, ...), each a short text; two match when every part does, and the parts that
// differ say why a stage is made again.
#include <map>
#include <string>
#include <vector>

#include "eitbench/bench/data/dataset.h"
#include "eitbench/bench/io/content_hash.h"

namespace eitbench::run {

using Provenance = std::map<std::string, std::string>;

// 16 hex digits of everything in `p`: the fingerprint results.json records.
std::string fingerprint(const Provenance& p);
// The parts that differ, or are in one and not the other: "data, snrs".
std::string differing_parts(const Provenance& stored, const Provenance& wanted);

// 16 hex digits of a data set's content: every array, the circles, the splits and the sensor.
std::string content_hash(const Dataset& data);
// Of a file's bytes ("" when there is no path): content_hash.h's.
using eitbench::file_hash;

}  // namespace eitbench::run
