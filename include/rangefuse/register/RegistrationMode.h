// Which of Tubic et al.'s registration algorithms run.
#pragma once

namespace rangefuse {

/// None; Algorithm 1 (incremental); Algorithm 2 (simultaneous); or 1 then 2.
enum class RegistrationMode { None, Incremental, Simultaneous, Both };

}  // namespace rangefuse
