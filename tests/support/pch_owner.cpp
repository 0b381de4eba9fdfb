// The target that owns the tests' precompiled header (tests/CMakeLists.txt); built, never run.
int main() { return 0; }
