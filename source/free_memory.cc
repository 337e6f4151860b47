#include <signorini/free_memory.h>

#include <cstdlib> // (defines __GLIBC__ with glibc)

#ifdef __GLIBC__
#  include <malloc.h>
#endif

namespace Signorini
{
  void
  return_free_memory_to_system()
  {
#ifdef __GLIBC__
    malloc_trim(0);
#endif
  }
} // namespace Signorini
