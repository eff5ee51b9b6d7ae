#include "qsp/version.h"

namespace qsp {

const char* version() noexcept { return QSP_VERSION; }

}  // namespace qsp
