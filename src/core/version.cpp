// The version the library was built as (freespace/version.hpp).
#include "freespace/version.hpp"

namespace freespace {

const char* LibraryVersion() { return FREESPACE_VERSION_STRING; }

}  // namespace freespace
