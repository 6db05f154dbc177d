// The hash of a sample's ray tree, for contrast sampling's comparison of
// trees (docs/scene-format.md, Rays): each branch (a miss, the material a
// ray met, a shadow ray's verdict) folded in, FNV-1a over words. Only the
// contrast variant that compares trees keeps it; elsewhere TREE_NOTE is
// nothing. Mirrors tree_word in src/base/tally.rs.
#ifndef TREE_GLSL
#define TREE_GLSL

#define TREE_BASIS 2166136261u
#define TREE_MISS 0u
#define TREE_HIT(material) ((material) + 1u)
#define TREE_SHADOW(blocked) (0x80000000u | ((blocked) ? 1u : 0u))

#ifdef CONTRAST_TREES
uint tree_hash = TREE_BASIS;
#define TREE_NOTE(word) tree_hash = (tree_hash ^ (word)) * 16777619u
#else
#define TREE_NOTE(word)
#endif

#endif
