/* Preloaded into the sanitizer runs (scripts/sanitize.sh): dlclose does nothing, so the Vulkan
   loader's ICD (lavapipe) and layers stay mapped until the process exits and LeakSanitizer's
   report at exit can name the library that made an allocation. Without it, a leak inside Mesa
   shows frames of "<unknown module>", which no suppression can match and which look the same as
   a leak anywhere else. Not part of fdmsurf. */
#include <stddef.h>

int dlclose(void* handle) {
    (void)handle;
    return 0;
}
