"""What is computed: the paper's closed form (`kernel`), inverse geometry and kinematics with every vector, the one result type (`forces`)."""
