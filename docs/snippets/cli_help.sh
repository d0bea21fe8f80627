bouncelab --help
echo "----"
bouncelab fit --help
echo "----"
bouncelab predict --help
