// SDL_Quit unloads the libraries SDL loaded (X11 extensions, dbus) and leaves their
// allocations unreachable: LeakSanitizer would report those libraries' memory as leaks. In
// sanitizer builds what SDL allocates (in a scope holding a NotLeakChecked) is not
// leak-checked; what wavemmlt's own code allocates is.
#pragma once
#if defined(__SANITIZE_ADDRESS__)
#include <sanitizer/lsan_interface.h>
#endif

namespace wmlt {

struct NotLeakChecked {
#if defined(__SANITIZE_ADDRESS__)
    NotLeakChecked() { __lsan_disable(); }
    ~NotLeakChecked() { __lsan_enable(); }
#else
    NotLeakChecked() {}
    ~NotLeakChecked() {}
#endif
};

}  // namespace wmlt
