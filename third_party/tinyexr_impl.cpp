// Sanitizer and fuzz builds only: the implementation of the Debian tinyexr header, instrumented
// (third_party/CMakeLists.txt).
#include <tinyexr.h>
