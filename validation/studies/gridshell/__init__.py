"""Studies of the robotic surface, the gridshell (seed 001, Fig. 4 and 5)."""
