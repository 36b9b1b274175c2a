// What glint-lab's commands share (lab_commands.h).
#include "glint/denoise/bank.h"
#include "glint/denoise/registry.h"
#include "lab_commands.h"

namespace glint::lab::cli {

std::string memberText(const denoise::FilterBank& bank, int m) {
    const denoise::BankMember& b = bank.members()[std::size_t(m)];
    return "#" + std::to_string(m) + " " + b.filter + " " +
           denoise::paramsSummary(denoise::findFilter(b.filter).params(), b.params);
}

}  // namespace glint::lab::cli
