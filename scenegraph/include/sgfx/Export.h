#pragma once
/// @file
/// SGFX_API marks the declarations sgfx's libraries export. The libraries are compiled with hidden
/// visibility (-fvisibility=hidden, inline functions too), so in a shared build only what the public
/// headers mark is in the dynamic symbol table: the API, and no internal helper that could clash with
/// or be interposed by another library's. Static builds carry the same marks, which do nothing there.
#if defined(__GNUC__) || defined(__clang__)
#define SGFX_API [[gnu::visibility("default")]]
#else
#define SGFX_API
#endif
