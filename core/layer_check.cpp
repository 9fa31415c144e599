// The layer check's program (core/CMakeLists.txt): it does nothing; what is checked is
// that it links from one layer's objects and those of the layers that layer declares.
int main() { return 0; }
