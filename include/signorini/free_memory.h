#ifndef signorini_free_memory_h
#define signorini_free_memory_h

namespace Signorini
{
  /**
   * Return the heap's free pages to the system. glibc keeps freed small
   * blocks for reuse, and a block allocated after them pins the heap, so the
   * memory of a large structure made of many small blocks (the refinement
   * hierarchy) stays resident after it is freed
   * and adds to the peak unless later allocations happen to reuse it. Call
   * it after freeing such a structure. A no-op without glibc.
   */
  void
  return_free_memory_to_system();
} // namespace Signorini

#endif
