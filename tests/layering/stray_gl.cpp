// Must NOT compile with core's flags: an OpenGL include in core/.
#include <GL/gl.h>
int main() { return 0; }
