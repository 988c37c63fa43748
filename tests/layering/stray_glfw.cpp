// Must NOT compile with core's flags: a GLFW include in core/.
#include <GLFW/glfw3.h>
int main() { return 0; }
