// The checks of the fdmsurf program's option combinations (options_check.cpp), made once every
// argument is read (options.cpp): each option's own value is checked as it is read, the options
// against each other here.
#pragma once

#include <string>

#include "cli/options.hpp"

namespace fdmsurf::cli {

// What the reading of the arguments saw that CliOptions does not keep.
struct ArgumentsSeen {
    bool explicit_model = false;  // --model N was given
    std::string fdm_only;         // the last FDM-only option given (they make no sense with edt)
};

// Checks the options against each other and settles what follows from them: --models all's
// model, --paper's settings where no option says otherwise, a .png OUTPUT as a picture.
// Throws Error(InvalidArgument) naming the options that conflict, or what is missing.
void check_combinations(CliOptions& o, const ArgumentsSeen& seen);

}  // namespace fdmsurf::cli
