#include "manylights/pass_times.h"

namespace ml {

const PassTime* PassTimes::find(std::string_view name) const {
    for (const PassTime& p : passes)
        if (p.name == name) return &p;
    return nullptr;
}

double PassTimes::ms(std::string_view name) const {
    const PassTime* p = find(name);
    return p ? p->ms : 0.0;
}

double PassTimes::totalMs() const {
    double t = 0;
    for (const PassTime& p : passes) t += p.ms;
    return t;
}

double PassTimes::groupMs(std::string_view group) const {
    double t = 0;
    for (const PassTime& p : passes)
        if (!group.empty() && p.group == group) t += p.ms;
    return t;
}

} // namespace ml
