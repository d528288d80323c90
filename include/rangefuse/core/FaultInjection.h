// Injected faults, for testing how a job fails when one rank does (tests/cli/rank_faults.sh).
#pragma once

#include <string>

namespace rangefuse {

/// Does what RANGEFUSE_FAULT asks when it names this point and this rank, else nothing.
/// RANGEFUSE_FAULT=POINT:ACTION@RANK, ACTION one of
///   throw  - throw InputError("<detail>: injected fault ..."), as a failed read or step would;
///   kill   - raise SIGKILL, as the out-of-memory killer or a lost node would.
/// RANGEFUSE_FAULT=POINT:ACTION@RANK#N acts on the N-th call of the point on that rank only.
/// Points: "read" (a scan file, detail = its path), "field" (mid-field, after a scan), "write"
/// (each write of an output: checkpoint dataset, mesh part, report, preview, poses).
void faultPoint(const char* point, const std::string& detail = "");

}  // namespace rangefuse
