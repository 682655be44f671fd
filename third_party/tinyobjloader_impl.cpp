// Sanitizer and fuzz builds only: the implementation of the Debian tinyobjloader header,
// instrumented (third_party/CMakeLists.txt).
#include <tiny_obj_loader.h>
