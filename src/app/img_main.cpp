// Placeholder: replaced by the wavemmlt-img tool.
int main() { return 0; }
