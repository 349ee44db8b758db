/* What the C tests (test_c_api.c, test_c_tracker.c) share: the allocation
 * counter (MASSID_TEST_COUNT_ALLOCATIONS: malloc interposed and counted) and
 * the CHECK macros. Included once per test program. */
#ifndef MASSID_C_TEST_SUPPORT_H
#define MASSID_C_TEST_SUPPORT_H

#include <stdio.h>
#include <stdlib.h>

#include "massid.h"

/* ---------------------------------------------------------------- allocations */

static long g_allocations = 0;

#if defined(MASSID_TEST_COUNT_ALLOCATIONS)
/* glibc's own allocator; the library's malloc calls (operator new included)
 * resolve to these definitions, which count and forward. */
extern void* __libc_malloc(size_t);
extern void* __libc_calloc(size_t, size_t);
extern void* __libc_realloc(void*, size_t);
extern void* __libc_memalign(size_t, size_t);
extern void __libc_free(void*);

void* malloc(size_t n) {
  ++g_allocations;
  return __libc_malloc(n);
}
void* calloc(size_t n, size_t size) {
  ++g_allocations;
  return __libc_calloc(n, size);
}
void* realloc(void* p, size_t n) {
  ++g_allocations;
  return __libc_realloc(p, n);
}
void* aligned_alloc(size_t alignment, size_t n) {
  ++g_allocations;
  return __libc_memalign(alignment, n);
}
int posix_memalign(void** out, size_t alignment, size_t n) {
  ++g_allocations;
  *out = __libc_memalign(alignment, n);
  return *out ? 0 : 12; /* ENOMEM */
}
void free(void* p) { __libc_free(p); }
#endif

/* ---------------------------------------------------------------- checks */

static int g_failures = 0;
static int g_checks = 0;

#define CHECK(cond)                                                            \
  do {                                                                         \
    ++g_checks;                                                                \
    if (!(cond)) {                                                             \
      ++g_failures;                                                            \
      fprintf(stderr, "%s:%d: check failed: %s\n", __FILE__, __LINE__, #cond); \
    }                                                                          \
  } while (0)

#define CHECK_CODE(expr, code)                                                                \
  do {                                                                                        \
    const int got_ = (expr);                                                                  \
    ++g_checks;                                                                               \
    if (got_ != (code)) {                                                                     \
      ++g_failures;                                                                           \
      fprintf(stderr, "%s:%d: %s returned %d (%s), expected %d\n", __FILE__, __LINE__, #expr, \
              got_, massid_error_string(got_), (code));                                       \
    }                                                                                         \
  } while (0)

#endif /* MASSID_C_TEST_SUPPORT_H */
