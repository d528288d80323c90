// Which of Tubic et al.'s registration algorithms run.
#pragma once

namespace rangefuse {

/// None; Algorithm 1 (incremental); Algorithm 2 (simultaneous); or 1 then 2.
enum class RegistrationMode { None, Incremental, Simultaneous, Both };

/// How Algorithm 2 fits: all poses in one joint solve per iteration (JointSolve.h), or each
/// scan on its own against the field (the paper's way, kept for comparison).
enum class RegistrationSolve { Joint, PerScan };

}  // namespace rangefuse
