// The dialect of shaders/common/: a subset of GLSL 4.60 that also compiles as
// C++20 with GLM (see shared_math.h). Rules for the files here:
//  - functions are declared SVO_FN, constants SVO_CONST (static in C++, so
//    that a host may include a file inside a struct, as the tracer's hosts do);
//  - float literals carry the f suffix (C++ would otherwise compute in double);
//  - no arrays, no out parameters: return a struct filled field by field
//    (lavapipe keeps a private array in memory: eight normals in one made
//    the trace kernel 2.1x slower there; tests/shaders/check_dialect.cmake
//    fails on any);
//  - work that only some lanes need goes outside loops whose trip counts
//    differ between lanes: lavapipe runs a SIMD group's loop body, with all
//    its work, while any lane is in it (tracer.glsl's while-while march,
//    luminaire.glsl's one loop over samples);
//  - a function that updates a large struct in place takes it as SVO_INOUT(T)
//    (GLSL inout, C++ a reference), so that C++ does not copy it in and out;
//    a large struct only read takes SVO_IN(T) (GLSL in, C++ a const
//    reference), and the function must not assign to it;
//  - GLSL built-ins only where GLM has the same name and meaning.
#ifndef SVO_PRELUDE_GLSL
#define SVO_PRELUDE_GLSL

#ifdef __cplusplus
#define SVO_FN inline
#define SVO_CONST static constexpr
#define SVO_INOUT(T) T&
#define SVO_IN(T) const T&
#else
#define SVO_FN
#define SVO_CONST const
#define SVO_INOUT(T) inout T
#define SVO_IN(T) in T
#endif

// bitCount and findLSB of one word: GLSL's built-ins; in C++ the same
// results without GLM's generic loops over bit fields.
#ifdef __cplusplus
SVO_FN int svo_bit_count(uint x) {
  x = x - ((x >> 1u) & 0x55555555u);
  x = (x & 0x33333333u) + ((x >> 2u) & 0x33333333u);
  x = (x + (x >> 4u)) & 0x0F0F0F0Fu;
  return int((x * 0x01010101u) >> 24u);
}
SVO_FN int svo_find_lsb(uint x) { return x == 0u ? -1 : __builtin_ctz(x); }
#else
SVO_FN int svo_bit_count(uint x) { return bitCount(x); }
SVO_FN int svo_find_lsb(uint x) { return findLSB(x); }
#endif

// exp(-x): zero from x = 104, where a float's exp(-x) is zero anyway; the C
// library reached that zero through its slow underflow path (about 1% of a
// mid view natively, in the Beckmann lobe's far tail).
SVO_FN float svo_exp_neg(float x) { return x < 104.0f ? exp(-x) : 0.0f; }

SVO_CONST float SVO_PI = 3.14159265358979f;
SVO_CONST float SVO_SQRT_PI = 1.77245385090552f;
SVO_CONST float SVO_SQRT2 = 1.41421356237310f;

#endif
