// Must NOT compile with core's flags: a Dear ImGui include in core/.
#include <imgui/imgui.h>
int main() { return 0; }
