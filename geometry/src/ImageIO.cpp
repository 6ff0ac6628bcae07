// TODO: implemented by the ImageIO work item
