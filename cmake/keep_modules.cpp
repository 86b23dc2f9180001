// Linked into every target of a sanitizer build (SVO_SANITIZE), and only there.
//
// The Vulkan loader dlcloses each driver when its instance is destroyed. With
// Mesa 22.3.6-1+deb12u2, a block that a driver's globals still point to is
// then unreachable, and LeakSanitizer reports it at exit as a 128-byte leak
// from "<unknown module>", which no suppression can name (every Vulkan test
// failed so). This dlclose keeps every loaded module mapped until the process
// exits: the block stays reachable from the driver's globals and is not
// reported, while a leak of ours still is.
extern "C" int dlclose(void*) { return 0; }
